// The embedding API (include/nsf/runtime.h) over the latent stepper. Everything but the facade is
// hidden in the shared library, so none of the Eigen, JSON or torch code it holds meets the
// host's own instantiations of them.
#include <nsf/runtime.h>
#include <omp.h>

#include <Eigen/Geometry>
#include <stdexcept>

#include "core/blas_threads.h"
#include "core/body_motion.h"
#include "core/error.h"
#include "mpm/colliders/collider_limits.h"
#include "mpm/colliders/rigid_collider.h"
#include "rom/setup/rom_setup.h"
#include "rom/step/latent_stepper.h"
#include "rom/step/step_guard.h"
#include "runtime/runtime_model.h"

namespace nsf {

namespace {

// Runs `f`, turning the library's own errors into std::runtime_error, the one type a host needs.
template <typename F>
auto guarded(const char* what, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("nsf::Runtime::") + what + ": " + e.what());
  }
}

void to_floats(const std::vector<Vec3>& v, float* out, std::size_t size, const char* what) {
  if (size < 3 * v.size())
    fail(what, ": the buffer holds ", size, " floats, ", 3 * v.size(), " are needed");
  for (std::size_t p = 0; p < v.size(); ++p)
    for (int k = 0; k < 3; ++k) out[3 * p + k] = float(v[p][k]);
}

// 3×3 matrices into out[0, 9·m.size()), row-major; throws when `size` is less.
void to_floats(const std::vector<Mat3>& m, float* out, std::size_t size, const char* what) {
  if (size < 9 * m.size())
    fail(what, ": the buffer holds ", size, " floats, ", 9 * m.size(), " are needed");
  for (std::size_t p = 0; p < m.size(); ++p)
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) out[9 * p + 3 * r + k] = float(m[p](r, k));
}

Vec3 vec(const std::array<double, 3>& a) {
  return Vec3(a[0], a[1], a[2]);
}
std::array<double, 3> arr(const Vec3& v) {
  return {v[0], v[1], v[2]};
}
std::array<double, 9> row_major(const Mat3& m) {
  return {m(0, 0), m(0, 1), m(0, 2), m(1, 0), m(1, 1), m(1, 2), m(2, 0), m(2, 1), m(2, 2)};
}

}  // namespace

struct Runtime::Impl {
  NeuralFields fields;
  int frames = 0;
  double frame_time = 0;
  ColliderLimits limits;                   // of set_collider_pose
  std::vector<std::string> warnings;       // the set-up's (RomSetup::warnings)
  std::unique_ptr<LatentStepper> stepper;  // holds a reference to `fields`
  std::unique_ptr<StepGuard> guard;        // and this one to `stepper`
  // Each scene object's particles, with their rest positions and masses, and the poses fitted to
  // them at step posed_at (−1: none yet).
  std::vector<Vec3> X;
  std::vector<double> mass;
  std::vector<std::vector<uint32_t>> members;
  std::vector<ObjectPose> poses;
  long posed_at = -1;
  double posed_time = 0;

  Impl(const std::string& model_path, const std::string& scene_path, const RuntimeOptions& o)
      : fields(load_runtime_model(model_path, o.threads)) {
    RomSetup s = rom_setup(fields, scene_path, o.mu, o.overrides, o.samples);
    frames = s.scene.settings.frames;
    frame_time = s.scene.settings.substeps * s.scene.settings.dt;
    limits = collider_limits(s.scene.settings);
    warnings = s.warnings;
    const Particles& P = s.scene.particles;
    X = P.X, mass = P.mass;
    const nlohmann::json& objects = s.scene.source.value("objects", nlohmann::json::array());
    members.resize(objects.size());
    for (uint32_t p = 0; p < P.object.size(); ++p) {
      if (P.object[p] >= members.size()) members.resize(P.object[p] + 1u);
      members[P.object[p]].push_back(p);
    }
    stepper = std::make_unique<LatentStepper>(fields, std::move(s.scene), s.mu, s.options);
    GuardOptions g;
    g.residual_cells = o.indicator_misfit_cells;
    g.courant = o.indicator_courant;
    g.grid_margin = o.indicator_grid_margin;
    g.recover = o.recover;
    guard = std::make_unique<StepGuard>(*stepper, g);
  }

  const ObjectPose& object_pose(std::size_t i) {
    if (i >= members.size()) fail("object ", i, " does not exist: the scene has ", members.size());
    if (posed_at != stepper->step_count() || posed_time != stepper->time()) {
      std::vector<Vec3> x, v;
      stepper->particle_state(x, &v);
      poses.assign(members.size(), ObjectPose{});
      for (std::size_t o = 0; o < members.size(); ++o) {
        if (members[o].empty()) continue;
        const BodyMotion b = fit_body_motion(X, x, v, mass, members[o]);
        ObjectPose& out = poses[o];
        out.position = arr(b.centre);
        out.rotation = row_major(b.rotation);
        out.velocity = arr(b.velocity);
        out.angular_velocity = arr(b.angular_velocity);
        out.rest_position = arr(b.rest_centre);
        out.misfit = b.rms_misfit;
      }
      posed_at = stepper->step_count(), posed_time = stepper->time();
    }
    return poses[i];
  }

  RigidCollider& collider(std::size_t i) const {
    auto& all = stepper->colliders();
    if (i >= all.size()) fail("collider ", i, " does not exist: the scene has ", all.size());
    auto* rigid = dynamic_cast<RigidCollider*>(all[i].get());
    if (!rigid) fail("collider ", i, " (", all[i]->type(), ") is not a rigid collider");
    return *rigid;
  }
};

Runtime::Runtime(const std::string& model_path, const std::string& scene_path,
                 const RuntimeOptions& options) {
  guarded("Runtime", [&] {
    if (options.threads < 0) fail("threads must be 0 (all cores) or more, got ", options.threads);
    if (options.threads > 0) omp_set_num_threads(options.threads);
    retain_freed_memory();  // the step's buffers are allocated anew each frame
    impl_ = std::make_unique<Impl>(model_path, scene_path, options);
  });
}
Runtime::~Runtime() = default;
Runtime::Runtime(Runtime&&) noexcept = default;
Runtime& Runtime::operator=(Runtime&&) noexcept = default;

std::size_t Runtime::particle_count() const {
  return impl_->stepper->particle_count();
}
int Runtime::frame_count() const {
  return impl_->frames;
}
double Runtime::frame_time() const {
  return impl_->frame_time;
}
int Runtime::steps_per_frame() const {
  return impl_->stepper->steps_per_frame();
}
double Runtime::time() const {
  return impl_->stepper->time();
}

void Runtime::advance_frame() {
  guarded("advance_frame", [&] { impl_->guard->advance_frame(); });
}
void Runtime::step() {
  guarded("step", [&] { impl_->guard->step(); });
}
const char* version() {
  return NSF_VERSION;
}

const char* build_arch() {
  return NSF_BUILD_ARCH;
}

std::vector<std::string> Runtime::warnings() const {
  return impl_->warnings;
}

RuntimeHealth Runtime::health() const {
  const RomHealth& h = impl_->guard->health();
  return {h.indicator,  h.residual_cells, h.courant,          h.grid_margin,   h.flagged,
          h.recoveries, h.last_recovery,  h.outside_training, h.steps_outside, h.training_note};
}

void Runtime::positions(float* out, std::size_t size) const {
  guarded("positions", [&] {
    std::vector<Vec3> x;
    impl_->stepper->particle_state(x, nullptr);
    to_floats(x, out, size, "positions");
  });
}
std::vector<float> Runtime::positions() const {
  std::vector<float> out(3 * particle_count());
  positions(out.data(), out.size());
  return out;
}
void Runtime::velocities(float* out, std::size_t size) const {
  guarded("velocities", [&] {
    std::vector<Vec3> x, v;
    impl_->stepper->particle_state(x, &v);
    to_floats(v, out, size, "velocities");
  });
}

void Runtime::stress(float* out, std::size_t size) const {
  guarded("stress", [&] {
    std::vector<Mat3> tau;
    impl_->stepper->particle_stress(tau);
    to_floats(tau, out, size, "stress");
  });
}
void Runtime::affine(float* out, std::size_t size) const {
  guarded("affine", [&] {
    std::vector<Mat3> C;
    impl_->stepper->particle_affine(C);
    to_floats(C, out, size, "affine");
  });
}
std::size_t Runtime::latent_dim() const {
  return std::size_t(impl_->stepper->latent().size());
}
void Runtime::latent(float* out, std::size_t size) const {
  guarded("latent", [&] {
    const Latent& z = impl_->stepper->latent();
    if (size < std::size_t(z.size()))
      fail("latent: the buffer holds ", size, " floats, ", z.size(), " are needed");
    for (Eigen::Index i = 0; i < z.size(); ++i) out[i] = float(z[i]);
  });
}

std::size_t Runtime::collider_count() const {
  return impl_->stepper->colliders().size();
}
std::string Runtime::collider_type(std::size_t i) const {
  return guarded("collider_type", [&] { return impl_->collider(i).type(); });
}
std::size_t Runtime::object_count() const {
  return impl_->members.size();
}
ObjectPose Runtime::object_pose(std::size_t i) const {
  return guarded("object_pose", [&] { return impl_->object_pose(i); });
}

ColliderPose Runtime::collider_pose(std::size_t i) const {
  return guarded("collider_pose", [&] {
    RigidCollider& c = impl_->collider(i);
    c.set_time(time());  // the next step sets it to this time too
    const RigidPose& p = c.pose();
    ColliderPose out;
    out.position = arr(p.center);
    out.rotation = row_major(p.rotation);
    out.velocity = arr(p.velocity);
    out.angular_velocity = arr(p.angular_velocity);
    return out;
  });
}
void Runtime::set_collider_pose(std::size_t i, const ColliderPose& pose) {
  guarded("set_collider_pose", [&] {
    RigidPose p;
    p.center = vec(pose.position);
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) p.rotation(r, k) = pose.rotation[3 * r + k];
    p.velocity = vec(pose.velocity);
    p.angular_velocity = vec(pose.angular_velocity);
    if (!p.center.allFinite() || !p.rotation.allFinite() || !p.velocity.allFinite() ||
        !p.angular_velocity.allFinite())
      fail("the pose of collider ", i, " holds a value that is not finite");
    if ((p.rotation.transpose() * p.rotation - Mat3::Identity()).norm() > 1e-4 ||
        p.rotation.determinant() < 0)
      fail("the rotation of collider ", i, " is not a rotation matrix (orthonormal, det +1)");
    const std::string out_of_bounds =
        collider_motion_problem(impl_->limits, i, p.center, p.velocity, p.angular_velocity);
    if (!out_of_bounds.empty()) fail(out_of_bounds);
    impl_->collider(i).drive(p, time());
  });
}

}  // namespace nsf
