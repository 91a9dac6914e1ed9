#include "rom/step/rigid_frames.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "nn/latent_inversion.h"

namespace nsf {

namespace {

Mat3 skew(const Vec3& a) {
  Mat3 s;
  s << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return s;
}

// SO(3)'s left Jacobian: ∂(exp([θ]×) y)/∂θ = −[exp([θ]×) y]× J_l(θ).
Mat3 left_jacobian(const Vec3& th) {
  const double a = th.norm();
  const Mat3 K = skew(th);
  if (a < 1e-8) return Mat3::Identity() + 0.5 * K;
  return Mat3::Identity() + (1 - std::cos(a)) / (a * a) * K +
         (a - std::sin(a)) / (a * a * a) * K * K;
}

class RigidSamples final : public SampleDeformation {
 public:
  RigidSamples(std::unique_ptr<SampleDeformation> inner, const RigidFrames& f,
               std::vector<uint32_t> ids)
      : inner_(std::move(inner)), f_(f), ids_(std::move(ids)) {}
  size_t size() const override { return inner_->size(); }
  void evaluate(const Eigen::VectorXd& z, std::vector<Vec3>& g) override {
    inner_->evaluate(z.head(f_.r), g);
    f_.apply(&ids_, z, g);
  }
  void jacobian(const Eigen::VectorXd& z, Eigen::MatrixXd& J, std::vector<Vec3>& g) override {
    Eigen::MatrixXd Jz;
    inner_->jacobian(z.head(f_.r), Jz, g);
    const int64_t n = int64_t(g.size()), r = f_.r;
    J.setZero(3 * n, f_.dim());
    std::vector<Mat3> R(static_cast<size_t>(f_.frames)), Jl(static_cast<size_t>(f_.frames));
    for (int k = 0; k < f_.frames; ++k) {
      R[size_t(k)] = f_.rotation(z, k);
      Jl[size_t(k)] = left_jacobian(z.segment<3>(r + 6 * k));
    }
    for (int64_t p = 0; p < n; ++p) {
      const int k = f_.frame[ids_[size_t(p)]];
      if (k < 0) {  // an object without a frame: g as it is
        J.block(3 * p, 0, 3, r) = Jz.block(3 * p, 0, 3, r);
        continue;
      }
      const Mat3& Rk = R[size_t(k)];
      const Vec3 y = Rk * (g[size_t(p)] - f_.pivot[size_t(k)]);
      J.block(3 * p, 0, 3, r) = Rk * Jz.block(3 * p, 0, 3, r);
      J.block<3, 3>(3 * p, r + 6 * k) = -skew(y) * Jl[size_t(k)];
      J.block<3, 3>(3 * p, r + 6 * k + 3) = Mat3::Identity();
      g[size_t(p)] = y + f_.pivot[size_t(k)] + f_.translation(z, k);
    }
  }

 private:
  std::unique_ptr<SampleDeformation> inner_;
  const RigidFrames& f_;
  std::vector<uint32_t> ids_;
};

class RigidDeformation final : public DeformationSource {
 public:
  RigidDeformation(std::unique_ptr<DeformationSource> inner, const RigidFrames& f)
      : inner_(std::move(inner)), f_(f) {}
  std::string describe() const override { return inner_->describe() + " in rigid frames"; }
  void set_points() override { inner_->set_points(); }
  void positions(const std::vector<uint32_t>& ids, const Latent& z, const Latent& now,
                 std::vector<Vec3>& x) override {
    inner_->positions(ids, f_.model(z), f_.model(now), x);
    f_.apply(&ids, z, x);
  }
  void positions_pair(const std::vector<uint32_t>& ids, const LatentPair& s, std::vector<Vec3>& x,
                      std::vector<Vec3>& x_prev) override {
    const Latent z = f_.model(s.z), zp = f_.model(s.z_prev);
    inner_->positions_pair(ids, {z, zp}, x, x_prev);
    f_.apply(&ids, s.z, x);
    f_.apply(&ids, s.z_prev, x_prev);
  }
  std::unique_ptr<SampleDeformation> samples(const std::vector<uint32_t>& S) override {
    return std::make_unique<RigidSamples>(inner_->samples(S), f_, S);
  }
  bool exact() const override { return inner_->exact(); }

 private:
  std::unique_ptr<DeformationSource> inner_;
  const RigidFrames& f_;
};

class RigidField final : public PointFieldSource {
 public:
  RigidField(std::unique_ptr<PointFieldSource> inner, const RigidFrames& f, bool rotate)
      : inner_(std::move(inner)), f_(f), rotate_(rotate) {}
  std::string describe() const override { return inner_->describe(); }
  void set_points() override { inner_->set_points(); }
  void evaluate(const std::vector<uint32_t>& ids, const LatentPair& s, bool for_step,
                std::vector<Mat3>& out) override {
    const Latent z = f_.model(s.z), zp = f_.model(s.z_prev);
    inner_->evaluate(ids, {z, zp}, for_step, out);
    if (rotate_) f_.turn(ids, s.z, out);
  }

 private:
  std::unique_ptr<PointFieldSource> inner_;
  const RigidFrames& f_;
  bool rotate_;
};

}  // namespace

Latent RigidFrames::augment(const Latent& z) const {
  if (!on()) return z;
  Latent out = Latent::Zero(dim());
  out.head(r) = z;
  return out;
}

Mat3 RigidFrames::rotation(const Latent& z, int f) const {
  const Vec3 th = z.segment<3>(r + 6 * f);
  const double a = th.norm();
  if (a < 1e-14) return Mat3::Identity();
  return Eigen::AngleAxisd(a, th / a).toRotationMatrix();
}

void RigidFrames::pose(const Latent& z, int f, Mat3& R, Vec3& offset) const {
  R = rotation(z, f);
  offset = pivot[size_t(f)] + translation(z, f) - R * pivot[size_t(f)];
}

int RigidFrames::frame_of_object(int o) const {
  for (int k = 0; k < frames; ++k)
    if (object_of[size_t(k)] == o) return k;
  return -1;
}

namespace {

// x_i ← R_k (x_i − c_k) + c_k + t_k with k = frame_of(i), for each i whose k is not −1.
template <typename FrameOf>
void move_into_frames(const RigidFrames& f, const Latent& z, std::vector<Vec3>& x,
                      FrameOf frame_of) {
  std::vector<Mat3> R(static_cast<size_t>(f.frames));
  std::vector<Vec3> shift(static_cast<size_t>(f.frames));
  for (int k = 0; k < f.frames; ++k) {
    R[size_t(k)] = f.rotation(z, k);
    shift[size_t(k)] = f.pivot[size_t(k)] + f.translation(z, k);
  }
  for (size_t i = 0; i < x.size(); ++i) {
    const int k = frame_of(i);
    if (k >= 0) x[i] = R[size_t(k)] * (x[i] - f.pivot[size_t(k)]) + shift[size_t(k)];
  }
}

}  // namespace

void RigidFrames::apply(const std::vector<uint32_t>* ids, const Latent& z,
                        std::vector<Vec3>& x) const {
  if (!on()) return;
  move_into_frames(*this, z, x, [&](size_t i) { return frame[ids ? (*ids)[i] : i]; });
}

void RigidFrames::apply_to_objects(const std::vector<uint16_t>& object, const Latent& z,
                                   std::vector<Vec3>& x) const {
  if (!on() || x.empty()) return;
  if (object.size() != x.size())
    fail("rigid frames: ", object.size(), " objects for ", x.size(), " points");
  std::vector<int> frame_of(size_t(*std::max_element(object.begin(), object.end())) + 1);
  for (size_t o = 0; o < frame_of.size(); ++o) frame_of[o] = frame_of_object(int(o));
  move_into_frames(*this, z, x, [&](size_t i) { return frame_of[object[i]]; });
}

void RigidFrames::turn(const std::vector<uint32_t>& ids, const Latent& z,
                       std::vector<Mat3>& f) const {
  if (!on()) return;
  std::vector<Mat3> R(static_cast<size_t>(frames));
  for (int k = 0; k < frames; ++k) R[size_t(k)] = rotation(z, k);
  for (size_t i = 0; i < ids.size(); ++i) {
    const int k = frame[ids[i]];
    if (k >= 0) f[i] = R[size_t(k)] * f[i] * R[size_t(k)].transpose();
  }
}

void RigidFrames::extend(size_t particles, const std::vector<uint32_t>& member) {
  frame.resize(particles);
  for (uint32_t p : member) frame.push_back(frame[p]);
}

RigidFrames make_rigid_frames(int r, const std::vector<int>& objects, const std::vector<Vec3>& X,
                              const std::vector<double>& mass,
                              const std::vector<uint16_t>& object) {
  RigidFrames f;
  f.r = r;
  if (objects.empty()) return f;
  int scene_objects = 0;
  for (uint16_t o : object) scene_objects = std::max(scene_objects, int(o) + 1);
  std::vector<int> frame_of(size_t(scene_objects), -1);
  for (int o : objects) {
    if (o < 0 || o >= scene_objects)
      fail("rom: rigid_frames names object ", o, ", and the scene has ", scene_objects,
           " (indices 0 to ", scene_objects - 1, ")");
    frame_of[size_t(o)] = f.frames++;
    f.object_of.push_back(o);
  }
  std::vector<double> m(size_t(f.frames), 0.0);
  f.pivot.assign(size_t(f.frames), Vec3::Zero());
  f.frame.resize(X.size());
  for (size_t p = 0; p < X.size(); ++p) {
    const int k = f.frame[p] = frame_of[object[p]];
    if (k < 0) continue;
    f.pivot[size_t(k)] += mass[p] * X[p];
    m[size_t(k)] += mass[p];
  }
  for (int k = 0; k < f.frames; ++k) {
    if (!(m[size_t(k)] > 0))
      fail("rom: rigid_frames names object ", f.object_of[size_t(k)], ", which has no mass");
    f.pivot[size_t(k)] /= m[size_t(k)];
  }
  return f;
}

std::unique_ptr<SampleDeformation> in_rigid_frames(std::unique_ptr<SampleDeformation> g,
                                                   const RigidFrames& frames,
                                                   std::vector<uint32_t> ids) {
  return std::make_unique<RigidSamples>(std::move(g), frames, std::move(ids));
}

std::unique_ptr<DeformationSource> in_rigid_frames(std::unique_ptr<DeformationSource> g,
                                                   const RigidFrames& frames) {
  return std::make_unique<RigidDeformation>(std::move(g), frames);
}

std::unique_ptr<PointFieldSource> in_rigid_frames(std::unique_ptr<PointFieldSource> f,
                                                  const RigidFrames& frames, bool rotate) {
  return std::make_unique<RigidField>(std::move(f), frames, rotate);
}

}  // namespace nsf
