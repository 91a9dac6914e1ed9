#include "nn/neural_fields.h"

#include "core/error.h"
#include "nn/coordinate_networks.h"
#include "nn/latent_inversion.h"
#include "nn/point_interpolation.h"

namespace nsf {

struct NeuralFields::Points::Impl {
  std::unique_ptr<CoordinateNetworks::Points> net;  // normalised rest positions (mlp)
  PointInterpolation weights;                       // per point, particles and weights (basis)
  bool particles = false;  // (basis) the points are the particles themselves, in order
  size_t count = 0;
};

namespace {

// A basis field at prepared points: dim values per point for coefficients c, then `put` turns
// each point's values into its output.
template <typename Put>
void basis_values(const PointBasis& b, bool particles, const PointInterpolation& w, size_t count,
                  const Eigen::VectorXf& c, Put&& put) {
  const int d = b.dim;
  const int64_t n = int64_t(count);
#pragma omp parallel for schedule(static) if (n > 4096)
  for (int64_t i = 0; i < n; ++i) {
    float v[9], acc[9] = {0};
    if (particles) {
      b.value(size_t(i), c, acc);
    } else {
      for (uint32_t e = w.start[size_t(i)]; e < w.start[size_t(i) + 1]; ++e) {
        b.value(w.particle[e], c, v);
        for (int k = 0; k < d; ++k) acc[k] += w.weight[e] * v[k];
      }
    }
    put(size_t(i), acc);
  }
}

}  // namespace

NeuralFields::Points::Points() = default;
NeuralFields::Points::~Points() = default;
NeuralFields::Points::Points(Points&&) noexcept = default;
NeuralFields::Points& NeuralFields::Points::operator=(Points&&) noexcept = default;
size_t NeuralFields::Points::size() const {
  return impl_ ? impl_->count : 0;
}

NeuralFields::NeuralFields() = default;
NeuralFields::~NeuralFields() = default;
NeuralFields::NeuralFields(NeuralFields&&) noexcept = default;
NeuralFields& NeuralFields::operator=(NeuralFields&&) noexcept = default;

namespace {

// What an MLP model's fields need and a torch-free NeuralFields lacks.
[[noreturn]] void needs_torch(const char* what) {
  fail(what,
       " needs LibTorch (the encoder or an MLP model's networks), and this model was loaded "
       "without it (the runtime and the Python module run basis models): use the nsf tool");
}

}  // namespace

NeuralFields NeuralFields::load_basis(const std::string& path) {
  return from_record(read_model_record(path));
}

NeuralFields NeuralFields::from_record(ModelRecord record,
                                       std::unique_ptr<CoordinateNetworks> networks) {
  const bool mlp = record.family == DecoderFamily::mlp;
  if (mlp && !networks)
    fail("model of scene '", record.scene.scene_name,
         "': an MLP model's record comes without its networks");
  if (!mlp && networks)
    fail("model of scene '", record.scene.scene_name,
         "': a basis model's record comes with networks, which it does not use");
  NeuralFields f;
  f.record_ = std::move(record);
  f.net_ = std::move(networks);
  return f;
}

DecoderFamily NeuralFields::family() const {
  return record_.family;
}
std::string NeuralFields::decoder() const {
  return family_name(record_.family);
}
const BasisDecoders* NeuralFields::bases() const {
  return record_.bases.get();
}

int NeuralFields::latent_dim() const {
  return record_.latent_dim;
}
size_t NeuralFields::particle_count() const {
  return size_t(record_.scene.particles);
}
const std::string& NeuralFields::scene_name() const {
  return record_.scene.scene_name;
}
bool NeuralFields::stress_uses_mu() const {
  return record_.stress_uses_mu;
}
const std::string* NeuralFields::attachment(const std::string& name) const {
  const auto it = record_.attachments.find(name);
  return it == record_.attachments.end() ? nullptr : &it->second;
}
double NeuralFields::mu_min() const {
  return record_.mu_min;
}
double NeuralFields::mu_max() const {
  return record_.mu_max;
}
const TrainingBox& NeuralFields::training_box() const {
  return record_.training_box;
}
double NeuralFields::train_seconds() const {
  return record_.train_seconds;
}
const std::string& NeuralFields::encoder_kind() const {
  if (!net_) needs_torch("the encoder's kind");
  return net_->encoder_kind();
}

Latent NeuralFields::rest_latent(const std::vector<Vec3>& X) const {
  if (record_.rest_latent.size() == latent_dim()) return record_.rest_latent;
  return encode(X);
}

std::unique_ptr<SampleDeformation> NeuralFields::sample_deformation(
    const std::vector<Vec3>& X, const std::vector<uint32_t>& ids) const {
  if (const BasisDecoders* b = bases()) {
    std::vector<Vec3> at(ids.size());
    for (size_t k = 0; k < ids.size(); ++k) at[k] = X[ids[k]];
    return std::make_unique<BasisSamples>(b->u.rows(ids), std::move(at));
  }
  if (!net_) needs_torch("g at sample particles");
  return net_->samples(*net_->prepare(X), ids);
}

void NeuralFields::check_scene(const std::string& scene_name, const std::vector<Vec3>& X,
                               const std::string& what) const {
  check_same_scene(record_.scene, SceneFingerprint::of(scene_name, X), what);
}

std::vector<Latent> NeuralFields::encode(const std::vector<std::vector<Vec3>>& frames) const {
  if (!net_) needs_torch("encoding a frame");
  const size_t P = particle_count();
  for (const auto& x : frames)
    if (x.size() != P)
      fail("encode: frame has ", x.size(), " particles, the model's scene has ", P);
  return net_->encode(frames);
}

Latent NeuralFields::encode(const std::vector<Vec3>& x) const {
  return encode(std::vector<std::vector<Vec3>>{x})[0];
}

NeuralFields::Points NeuralFields::prepare(const std::vector<Vec3>& X) const {
  Points p;
  p.impl_ = std::make_unique<Points::Impl>();
  p.impl_->count = X.size();
  const BasisDecoders* b = bases();
  if (!b) {
    if (!net_) needs_torch("an MLP model's fields");
    p.impl_->net = net_->prepare(X);
    return p;
  }
  p.impl_->particles = X.size() == b->rest.size();
  for (size_t i = 0; p.impl_->particles && i < X.size(); ++i)
    p.impl_->particles = (X[i] - b->rest[i]).norm() <= 1e-6 * (1 + X[i].norm());
  if (!p.impl_->particles) p.impl_->weights = interpolate_points(b->rest, X);
  return p;
}

void NeuralFields::deform(const Points& X, const Latent& z, std::vector<Vec3>& x) const {
  x.resize(X.size());
  if (const BasisDecoders* b = bases()) {
    if (z.size() != latent_dim())
      fail("latent of size ", z.size(), " for a model with r = ", latent_dim());
    const auto& pts = *X.impl_;
    // g = X + (mean + B c) at each particle; at other points the particles' g interpolated.
    const std::vector<Vec3>& rest = b->rest;
    const PointBasis& u = b->u;
    const Eigen::VectorXf c = b->deformation_coefficients(z);
    const int64_t n = int64_t(pts.count);
#pragma omp parallel for schedule(static) if (n > 4096)
    for (int64_t i = 0; i < n; ++i) {
      float d[3];
      if (pts.particles) {
        u.value(size_t(i), c, d);
        x[size_t(i)] = rest[size_t(i)] + Vec3(d[0], d[1], d[2]);
        continue;
      }
      Vec3 acc = Vec3::Zero();
      const PointInterpolation& w = pts.weights;
      for (uint32_t e = w.start[size_t(i)]; e < w.start[size_t(i) + 1]; ++e) {
        u.value(w.particle[e], c, d);
        acc += double(w.weight[e]) * (rest[w.particle[e]] + Vec3(d[0], d[1], d[2]));
      }
      x[size_t(i)] = acc;
    }
    return;
  }
  if (z.size() != latent_dim())
    fail("latent of size ", z.size(), " for a model with r = ", latent_dim());
  net_->deform(*X.impl_->net, nullptr, {&z}, x);
}

void NeuralFields::stress(const Points& X, const Latent& z, double mu, std::vector<Mat3>& tau,
                          const Latent* zdot) const {
  tau.resize(X.size());
  if (const BasisDecoders* b = bases()) {
    basis_values(b->tau, X.impl_->particles, X.impl_->weights, X.size(),
                 b->stress_coefficients(z, mu, zdot),
                 [&](size_t i, const float* s) {  // xx yy zz xy yz xz
                   tau[i] << s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2];
                 });
    return;
  }
  if (z.size() != latent_dim())
    fail("latent of size ", z.size(), " for a model with r = ", latent_dim());
  net_->stress(*X.impl_->net, nullptr, z, mu, tau);
}

void NeuralFields::affine(const Points& X, const Latent& z, std::vector<Mat3>& C, double mu,
                          const Latent* zdot) const {
  C.resize(X.size());
  if (const BasisDecoders* b = bases()) {
    basis_values(b->C, X.impl_->particles, X.impl_->weights, X.size(),
                 b->affine_coefficients(z, mu, zdot), [&](size_t i, const float* c) {  // row-major
                   C[i] << c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8];
                 });
    return;
  }
  if (z.size() != latent_dim())
    fail("latent of size ", z.size(), " for a model with r = ", latent_dim());
  net_->affine(*X.impl_->net, nullptr, z, C);
}

}  // namespace nsf
