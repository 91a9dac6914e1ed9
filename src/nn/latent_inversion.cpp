// GCC 12 reports false -Wmaybe-uninitialized warnings from inside Eigen's AVX-512 kernels for
// dynamic-size products (in the intrinsics headers, not in this code).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include "nn/latent_inversion.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "core/dense_kernels.h"
#include "core/error.h"

namespace nsf {

BasisSamples::BasisSamples(PointBasis u, std::vector<Vec3> rest)
    : u_(std::move(u)), rest_(std::move(rest)) {}

// The samples' rows are contiguous (3|S| × K, row-major): g at every sample is the rows against
// c, and ∂g/∂ẑ the rows against ∂c/∂ẑ's columns, in one pass over the rows
// (core/dense_kernels.h).
void BasisSamples::evaluate(const Eigen::VectorXd& z, std::vector<Vec3>& g) {
  const Eigen::VectorXf c = u_.net(z).cast<float>();
  const int64_t rows = 3 * int64_t(rest_.size());
  // Local, not a member: training and the error budget invert frames on several threads at once.
  std::vector<float> out(static_cast<size_t>(rows));
  rows_times_vectors(u_.modes.data(), rows, u_.K, c.data(), 1, out.data());
  positions(out.data(), 1, g);
}

void BasisSamples::jacobian(const Eigen::VectorXd& z, Eigen::MatrixXd& J, std::vector<Vec3>& g) {
  Eigen::MatrixXd dc;  // K × r
  const Eigen::VectorXd c = u_.net(z, &dc);
  const int64_t rows = 3 * int64_t(rest_.size()), r = dc.cols(), K = u_.K;
  // The right-hand sides one after another: c, then each column of ∂c/∂ẑ.
  Eigen::MatrixXf V(K, 1 + r);
  V.col(0) = c.cast<float>();
  V.rightCols(r) = dc.cast<float>();
  const int cols = int(1 + r);
  std::vector<float> out(static_cast<size_t>(rows * cols));
  rows_times_vectors(u_.modes.data(), rows, int(K), V.data(), cols, out.data());
  J.resize(rows, r);
  for (int64_t i = 0; i < rows; ++i)
    for (int64_t j = 0; j < r; ++j) J(i, j) = out[size_t(i * cols + 1 + j)];
  positions(out.data(), cols, g);
}

void BasisSamples::positions(const float* products, int stride, std::vector<Vec3>& g) const {
  g.resize(rest_.size());
  for (size_t p = 0; p < rest_.size(); ++p)
    for (int a = 0; a < 3; ++a)
      g[p][a] = rest_[p][a] + (u_.mean[3 * p + a] + products[(3 * p + a) * size_t(stride)]);
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
  // The penalty's weight: |S| ε², so that its term and the samples' misfit share units (m²).
  const double lambda = options.penalty && options.penalty_length > 0
                            ? double(n) * options.penalty_length * options.penalty_length
                            : 0.0;
  const auto penalty_at = [&](const Eigen::VectorXd& z) {
    return lambda > 0 ? options.penalty->terms(z) : LatentPenalty::Terms{};
  };
  // The penalty's Gauss–Newton terms at ẑ; the line search finds them for the step it accepts,
  // which is the next iteration's ẑ.
  LatentPenalty::Terms penalty = penalty_at(res.z);
  for (int it = 0; it < iterations; ++it) {
    samples.jacobian(res.z, J, g);
    Eigen::VectorXd residual(3 * n);
    for (int64_t p = 0; p < n; ++p) residual.segment<3>(3 * p) = g[p] - target[p];
    const double r0 = residual.squaredNorm() + lambda * penalty.distance2;
    res.rms_residual = std::sqrt(residual.squaredNorm() / double(n));
    // Normal equations are r × r; a tiny Levenberg term keeps them solvable when some latent
    // direction does not move the samples at all.
    Eigen::MatrixXd JtJ = J.transpose() * J;
    JtJ.diagonal().array() +=
        options.damping * JtJ.diagonal().array() + 1e-10 * (1.0 + JtJ.diagonal().maxCoeff());
    Eigen::VectorXd rhs = -(J.transpose() * residual);
    if (lambda > 0) {
      JtJ += lambda * penalty.hessian;
      rhs -= lambda * penalty.gradient;
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
    // the latent must never fit the samples (plus the penalty's term) worse than where it started.
    bool accepted = false;
    for (int halvings = 0; halvings < 6; ++halvings) {
      const double d1 = squared_residual(samples, res.z + dz, target, trial);
      LatentPenalty::Terms penalty1 = penalty_at(res.z + dz);
      const double r1 = d1 + lambda * penalty1.distance2;
      if (r1 < r0) {
        res.z += dz;
        penalty = std::move(penalty1);
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

}  // namespace nsf
