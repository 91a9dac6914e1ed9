// GCC 12 reports false -Wmaybe-uninitialized warnings from inside Eigen's AVX-512 kernels for
// dynamic-size products (in the intrinsics headers, not in this code).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include "nn/latent_inversion.h"

#include <torch/autograd.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <exception>

#include "core/error.h"
#include "nn/basis_export.h"
#include "nn/latent_prior.h"
#include "nn/model.h"
#include "nn/torch_settings.h"

namespace nsf {

void deformation_jacobian(NeuralModel& model, const torch::Tensor& Xn, const Eigen::VectorXd& z,
                          Eigen::MatrixXd& J, std::vector<Vec3>& g) {
  const int64_t n = Xn.size(0), r = z.size();
  const torch::Tensor zt =
      torch::from_blob(const_cast<double*>(z.data()), {1, r}, torch::kFloat64).to(torch::kFloat32);
  // One copy of ẑ per point, so the gradient of Σ_p g_c(X_p, ẑ_p) with respect to the copies
  // holds every point's own row ∂g_c(X_p)/∂ẑ.
  torch::Tensor zrep = zt.expand({n, r}).clone().set_requires_grad(true);
  const torch::Tensor out = model.deform(Xn, zrep);  // n × 3
  J.resize(3 * n, r);
  for (int c = 0; c < 3; ++c) {
    const auto grads = torch::autograd::grad({out.select(1, c).sum()}, {zrep}, {},
                                             /*retain_graph=*/c < 2);
    const torch::Tensor G = grads[0].to(torch::kFloat64).contiguous();
    const double* Gp = G.data_ptr<double>();
    for (int64_t p = 0; p < n; ++p)
      for (int64_t k = 0; k < r; ++k) J(3 * p + c, k) = Gp[p * r + k];
  }
  const torch::Tensor o = out.detach().to(torch::kFloat64).contiguous();
  g.resize(n);
  const double* op = o.data_ptr<double>();
  for (int64_t p = 0; p < n; ++p) g[p] = Vec3(op[3 * p], op[3 * p + 1], op[3 * p + 2]);
}

NetworkSamples::NetworkSamples(NeuralModel& model, torch::Tensor Xn)
    : model_(model), Xn_(std::move(Xn)) {}

size_t NetworkSamples::size() const {
  return size_t(Xn_.size(0));
}

void NetworkSamples::evaluate(const Eigen::VectorXd& z, std::vector<Vec3>& g) {
  torch::NoGradGuard no_grad;
  const int64_t n = Xn_.size(0), r = z.size();
  const torch::Tensor zt =
      torch::from_blob(const_cast<double*>(z.data()), {1, r}, torch::kFloat64).to(torch::kFloat32);
  const torch::Tensor o = model_.deform(Xn_, zt.expand({n, r})).to(torch::kFloat64).contiguous();
  const double* op = o.data_ptr<double>();
  g.resize(n);
  for (int64_t p = 0; p < n; ++p) g[p] = Vec3(op[3 * p], op[3 * p + 1], op[3 * p + 2]);
}

void NetworkSamples::jacobian(const Eigen::VectorXd& z, Eigen::MatrixXd& J, std::vector<Vec3>& g) {
  deformation_jacobian(model_, Xn_, z, J, g);
}

BasisSamples::BasisSamples(PointBasis u, std::vector<Vec3> rest)
    : u_(std::move(u)), rest_(std::move(rest)) {}

// The samples' rows are contiguous (3|S| × K, row-major), so g and ∂g/∂ẑ at every sample are one
// matrix-vector and one matrix-matrix product.
namespace {
using RowMajorXf = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
}

void BasisSamples::evaluate(const Eigen::VectorXd& z, std::vector<Vec3>& g) {
  const Eigen::VectorXf c = u_.net(z).cast<float>();
  const int64_t rows = 3 * int64_t(rest_.size());
  const Eigen::VectorXf d = Eigen::Map<const Eigen::VectorXf>(u_.mean.data(), rows) +
                            Eigen::Map<const RowMajorXf>(u_.modes.data(), rows, u_.K) * c;
  g.resize(rest_.size());
  for (size_t p = 0; p < rest_.size(); ++p)
    g[p] = rest_[p] + Vec3(d[3 * p], d[3 * p + 1], d[3 * p + 2]);
}

void BasisSamples::jacobian(const Eigen::VectorXd& z, Eigen::MatrixXd& J, std::vector<Vec3>& g) {
  Eigen::MatrixXd dc;  // K × r
  const Eigen::VectorXf c = u_.net(z, &dc).cast<float>();
  const int64_t rows = 3 * int64_t(rest_.size());
  const Eigen::Map<const RowMajorXf> B(u_.modes.data(), rows, u_.K);
  const Eigen::VectorXf d = Eigen::Map<const Eigen::VectorXf>(u_.mean.data(), rows) + B * c;
  J = (B * dc.cast<float>()).cast<double>();
  g.resize(rest_.size());
  for (size_t p = 0; p < rest_.size(); ++p)
    g[p] = rest_[p] + Vec3(d[3 * p], d[3 * p + 1], d[3 * p + 2]);
}

std::unique_ptr<SampleDeformation> sample_deformation(NeuralModel& model,
                                                      const std::vector<Vec3>& rest,
                                                      const std::vector<uint32_t>& ids) {
  std::vector<Vec3> X(ids.size());
  for (size_t k = 0; k < ids.size(); ++k) X[k] = rest[ids[k]];
  if (model.is_basis()) return std::make_unique<BasisSamples>(point_basis(model, 0, &ids), X);
  const torch::Tensor Xn =
      model.norm_X.apply(torch::from_blob(X.data()->data(), {int64_t(X.size()), 3}, torch::kFloat64)
                             .to(torch::kFloat32));
  return std::make_unique<NetworkSamples>(model, Xn);
}

namespace {

// Σ‖g(X_p, ẑ) − target_p‖², with g(X_p, ẑ) left in `g`.
double squared_residual(SampleDeformation& samples, const Eigen::VectorXd& z,
                        const std::vector<Vec3>& target, std::vector<Vec3>& g) {
  samples.evaluate(z, g);
  double sum = 0;
  for (size_t p = 0; p < g.size(); ++p) sum += (g[p] - target[p]).squaredNorm();
  return sum;
}

}  // namespace

InversionResult invert_deformation(NeuralModel& model, const torch::Tensor& Xn,
                                   const std::vector<Vec3>& target, const Eigen::VectorXd& z0,
                                   const GaussNewtonOptions& options) {
  NetworkSamples samples(model, Xn);
  return invert_deformation(samples, target, z0, options);
}

InversionResult invert_deformation(SampleDeformation& samples, const std::vector<Vec3>& target,
                                   const Eigen::VectorXd& z0, const GaussNewtonOptions& options) {
  const int64_t n = int64_t(samples.size()), r = z0.size();
  if (int64_t(target.size()) != n)
    fail("inversion: ", target.size(), " target positions for ", n, " sample particles");
  if (3 * n < r)
    fail("inversion: |S| = ", n, " sample particles cannot fix r = ", r,
         " latent coordinates (need |S| ≥ r/3)");
  if (!z0.allFinite())
    fail(
        "inversion: the starting latent holds a NaN or infinite value (a damaged model, or a "
        "state that diverged)");
  for (const Vec3& x : target)
    if (!x.allFinite()) fail("inversion: a target position holds a NaN or infinite value");
  InversionResult res;
  res.z = z0;
  Eigen::MatrixXd J;
  std::vector<Vec3> g, trial;
  const int iterations = options.taylor ? 1 : std::max(1, options.max_iterations);
  // The latent prior's weight: |S| ε², so that its term and the samples' misfit share units (m²).
  const double lambda = options.prior && options.prior_length > 0
                            ? double(n) * options.prior_length * options.prior_length
                            : 0.0;
  const auto prior_at = [&](const Eigen::VectorXd& z) {
    return lambda > 0 ? options.prior->nearest(z) : LatentPrior::Nearest{};
  };
  // The prior's Gauss–Newton terms come from the closest point of its surface to ẑ; the line
  // search finds it for the step it accepts, which is the next iteration's ẑ.
  LatentPrior::Nearest near = prior_at(res.z);
  for (int it = 0; it < iterations; ++it) {
    samples.jacobian(res.z, J, g);
    Eigen::VectorXd residual(3 * n);
    for (int64_t p = 0; p < n; ++p) residual.segment<3>(3 * p) = g[p] - target[p];
    const double r0 = residual.squaredNorm() + lambda * near.distance2;
    res.rms_residual = std::sqrt(residual.squaredNorm() / double(n));
    // Normal equations are r × r; a tiny Levenberg term keeps them solvable when some latent
    // direction does not move the samples at all.
    Eigen::MatrixXd JtJ = J.transpose() * J;
    JtJ.diagonal().array() += 1e-10 * (1.0 + JtJ.diagonal().maxCoeff());
    Eigen::VectorXd rhs = -(J.transpose() * residual);
    if (lambda > 0) {
      JtJ += lambda * near.hessian;
      rhs -= lambda * near.gradient;
    }
    Eigen::VectorXd dz = JtJ.ldlt().solve(rhs);
    if (!dz.allFinite())
      fail("inversion: the Gauss–Newton step is not finite (iteration ", it + 1, ")");
    res.iterations = it + 1;
    res.fitted = g;
    if (options.taylor) {  // the linearised update as it stands, by definition
      res.z += dz;
      res.fitted.clear();  // g at the stepped latent was never evaluated
      break;
    }
    // Backtracking: a full Gauss–Newton step can overshoot where g is strongly nonlinear in ẑ;
    // the latent must never fit the samples (plus the prior's term) worse than where it started.
    bool accepted = false;
    for (int halvings = 0; halvings < 6; ++halvings) {
      const double d1 = squared_residual(samples, res.z + dz, target, trial);
      LatentPrior::Nearest near1 = prior_at(res.z + dz);
      const double r1 = d1 + lambda * near1.distance2;
      if (r1 < r0) {
        res.z += dz;
        near = std::move(near1);
        res.fitted.swap(trial);
        res.rms_residual = std::sqrt(d1 / double(n));
        accepted = true;
        break;
      }
      dz *= 0.5;
    }
    if (!accepted || dz.norm() <= options.tolerance * (1.0 + res.z.norm())) break;
  }
  return res;
}

FrameLatentRefiner::FrameLatentRefiner(NeuralModel& model, const std::vector<Vec3>& rest,
                                       int iterations) {
  const size_t P = rest.size(), m = std::min(kMaxParticles, P);
  std::vector<uint32_t> ids;
  for (size_t i = 0; i < m; ++i) ids_.push_back(i * P / m), ids.push_back(uint32_t(ids_.back()));
  g_ = sample_deformation(model, rest, ids);
  options_.max_iterations = iterations;
  options_.tolerance = 1e-7;
}

Eigen::VectorXd FrameLatentRefiner::refine(const float* x, const Eigen::VectorXd& start) const {
  std::vector<Vec3> target;
  target.reserve(ids_.size());
  for (size_t p : ids_) target.emplace_back(x[3 * p], x[3 * p + 1], x[3 * p + 2]);
  return invert_deformation(*g_, target, start, options_).z;
}

void FrameLatentRefiner::refine_many(const std::vector<const float*>& x,
                                     std::vector<Eigen::VectorXd>& z) const {
  if (x.size() != z.size()) fail("refine_many: ", x.size(), " frames but ", z.size(), " starts");
  // As many frames at a time as the GEMMs had threads; each of those threads gets one frame.
  const int threads = int(
      std::min<size_t>(std::max<size_t>(1, x.size()), size_t(std::max(1, blas_thread_count()))));
  const ScopedBlasThreads one_blas_thread(1);
  std::vector<std::exception_ptr> errors(x.size());
  // Inside an OpenMP region torch and Eigen run each frame's operations serially.
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
  for (size_t k = 0; k < x.size(); ++k) {
    try {
      z[k] = refine(x[k], z[k]);
    } catch (...) {
      errors[k] = std::current_exception();
    }
  }
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace nsf
