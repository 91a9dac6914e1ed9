#include "nn/neural_fields.h"

#include "core/error.h"
#include "nn/basis_export.h"
#include "nn/model.h"
#include "nn/point_interpolation.h"

namespace nsf {

namespace {

// Bounds the activations of one call (points × width floats per layer) for large point sets.
constexpr int64_t kChunk = 65536;

torch::Tensor latent_tensor(const Latent& z, int64_t r) {
  if (z.size() != r) fail("latent of size ", z.size(), " for a model with r = ", r);
  return torch::from_blob(const_cast<double*>(z.data()), {1, r}, torch::kFloat64)
      .to(torch::kFloat32);
}

torch::Tensor positions_tensor(const std::vector<Vec3>& v) {
  return torch::from_blob(const_cast<double*>(v.data()->data()), {int64_t(v.size()), 3},
                          torch::kFloat64)
      .to(torch::kFloat32);
}

// Runs f over chunks of the prepared points and returns the concatenated rows as double.
template <typename F>
torch::Tensor chunked(const torch::Tensor& Xn, const torch::Tensor& z, F&& f) {
  torch::NoGradGuard no_grad;
  const int64_t n = Xn.size(0);
  std::vector<torch::Tensor> parts;
  for (int64_t a = 0; a < n; a += kChunk) {
    const torch::Tensor X = Xn.slice(0, a, std::min(n, a + kChunk));
    parts.push_back(f(X, z.expand({X.size(0), z.size(1)})));
  }
  if (parts.empty()) return torch::empty({0, 0}, torch::kFloat64);
  return torch::cat(parts, 0).to(torch::kFloat64).contiguous();
}

}  // namespace

struct NeuralFields::Points::Impl {
  torch::Tensor Xn;            // N × 3 normalised rest positions (mlp)
  PointInterpolation weights;  // per point, particles and weights (basis)
  bool particles = false;      // (basis) the points are the particles themselves, in order
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

NeuralFields NeuralFields::load(const std::string& path) {
  NeuralFields f;
  f.model_ = std::make_unique<NeuralModel>(NeuralModel::load(path));
  if (f.model_->is_basis()) f.bases_ = std::make_unique<BasisDecoders>(basis_decoders(*f.model_));
  return f;
}

DecoderFamily NeuralFields::family() const {
  return model_->config.decoder;
}
std::string NeuralFields::decoder() const {
  return family_name(model_->config.decoder);
}
const BasisDecoders* NeuralFields::bases() const {
  return bases_.get();
}

int NeuralFields::latent_dim() const {
  return model_->config.latent_dim;
}
size_t NeuralFields::particle_count() const {
  return size_t(model_->scene.particles);
}
const std::string& NeuralFields::scene_name() const {
  return model_->scene.scene_name;
}
bool NeuralFields::stress_uses_mu() const {
  return model_->stress_has_mu();
}
double NeuralFields::calibrated_latent_prior(bool tracked) const {
  return (tracked ? model_->tracked_calibration : model_->calibration).latent_prior;
}
double NeuralFields::calibrated_dt_ratio(bool tracked) const {
  return (tracked ? model_->tracked_calibration : model_->calibration).dt_ratio;
}
double NeuralFields::mu_min() const {
  return model_->mu_min;
}
double NeuralFields::mu_max() const {
  return model_->mu_max;
}
const TrainingBox& NeuralFields::training_box() const {
  return model_->training_box;
}
double NeuralFields::train_seconds() const {
  return model_->train_seconds;
}
NeuralModel& NeuralFields::model() {
  return *model_;
}

void NeuralFields::check_scene(const std::string& scene_name, const std::vector<Vec3>& X,
                               const std::string& what) const {
  model_->check_scene(SceneFingerprint::of(scene_name, X), what);
}

std::vector<Latent> NeuralFields::encode(const std::vector<std::vector<Vec3>>& frames) const {
  torch::NoGradGuard no_grad;
  const int64_t P = model_->scene.particles;
  std::vector<Latent> out;
  for (const auto& x : frames) {
    if (int64_t(x.size()) != P)
      fail("encode: frame has ", x.size(), " particles, the model's scene has ", P);
    const torch::Tensor z =
        model_->encode(positions_tensor(x).reshape({1, P, 3})).to(torch::kFloat64).contiguous();
    out.emplace_back(Eigen::Map<const Latent>(z.data_ptr<double>(), z.size(1)));
  }
  return out;
}

Latent NeuralFields::encode(const std::vector<Vec3>& x) const {
  return encode(std::vector<std::vector<Vec3>>{x})[0];
}

NeuralFields::Points NeuralFields::prepare(const std::vector<Vec3>& X) const {
  Points p;
  p.impl_ = std::make_unique<Points::Impl>();
  p.impl_->count = X.size();
  if (!bases_) {
    p.impl_->Xn = X.empty() ? torch::empty({0, 3}) : model_->norm_X.apply(positions_tensor(X));
    return p;
  }
  p.impl_->particles = X.size() == bases_->rest.size();
  for (size_t i = 0; p.impl_->particles && i < X.size(); ++i)
    p.impl_->particles = (X[i] - bases_->rest[i]).norm() <= 1e-6 * (1 + X[i].norm());
  if (!p.impl_->particles) p.impl_->weights = interpolate_points(bases_->rest, X);
  return p;
}

void NeuralFields::deform(const Points& X, const Latent& z, std::vector<Vec3>& x) const {
  x.resize(X.size());
  if (bases_) {
    if (z.size() != latent_dim())
      fail("latent of size ", z.size(), " for a model with r = ", latent_dim());
    const auto& pts = *X.impl_;
    // g = X + (mean + B c) at each particle; at other points the particles' g interpolated.
    const std::vector<Vec3>& rest = bases_->rest;
    const PointBasis& u = bases_->u;
    const Eigen::VectorXf c = bases_->deformation_coefficients(z);
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
  const torch::Tensor out =
      chunked(X.impl_->Xn, latent_tensor(z, latent_dim()),
              [&](const auto& a, const auto& b) { return model_->deform(a, b); });
  if (!x.empty()) std::copy_n(out.data_ptr<double>(), 3 * x.size(), x[0].data());
}

void NeuralFields::stress(const Points& X, const Latent& z, double mu, std::vector<Mat3>& tau,
                          const Latent* zdot) const {
  tau.resize(X.size());
  if (bases_) {
    basis_values(bases_->tau, X.impl_->particles, X.impl_->weights, X.size(),
                 bases_->stress_coefficients(z, mu, zdot),
                 [&](size_t i, const float* s) {  // xx yy zz xy yz xz
                   tau[i] << s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2];
                 });
    return;
  }
  const torch::Tensor m = torch::full({1, 1}, float(mu));
  const torch::Tensor out =
      chunked(X.impl_->Xn, latent_tensor(z, latent_dim()), [&](const auto& a, const auto& b) {
        return model_->stress(a, b, m.expand({a.size(0), 1}));
      });
  tau.resize(X.size());
  const double* s = tau.empty() ? nullptr : out.data_ptr<double>();
  for (size_t p = 0; p < tau.size(); ++p, s += 6)  // xx yy zz xy yz xz
    tau[p] << s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2];
}

void NeuralFields::affine(const Points& X, const Latent& z, std::vector<Mat3>& C, double mu,
                          const Latent* zdot) const {
  C.resize(X.size());
  if (bases_) {
    basis_values(bases_->C, X.impl_->particles, X.impl_->weights, X.size(),
                 bases_->affine_coefficients(z, mu, zdot),
                 [&](size_t i, const float* c) {  // row-major
                   C[i] << c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8];
                 });
    return;
  }
  const torch::Tensor out =
      chunked(X.impl_->Xn, latent_tensor(z, latent_dim()),
              [&](const auto& a, const auto& b) { return model_->affine(a, b); });
  C.resize(X.size());
  const double* c = C.empty() ? nullptr : out.data_ptr<double>();
  for (size_t p = 0; p < C.size(); ++p, c += 9)  // row-major, as in the run files
    C[p] << c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8];
}

}  // namespace nsf
