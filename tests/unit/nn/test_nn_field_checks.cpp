// The yardsticks behind `nsf eval`'s poly and force columns (nn/field_checks.h).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "nn/field_checks.h"

namespace {

using nsf::Mat3;
using nsf::Vec3;

// A lattice of particles, two per cell along each axis, filling [0.3, 0.7]³ (Δx = 0.05).
std::vector<Vec3> lattice() {
  std::vector<Vec3> X;
  for (int i = 0; i < 16; ++i)
    for (int j = 0; j < 16; ++j)
      for (int k = 0; k < 16; ++k)
        X.emplace_back(0.3 + 0.025 * (i + 0.5), 0.3 + 0.025 * (j + 0.5), 0.3 + 0.025 * (k + 0.5));
  return X;
}

Mat3 smooth_field(const Vec3& X) {
  Mat3 m;
  m << X.x() * X.y(), 1.0, X.z() * X.z() * X.x(), 0.5, X.y() * X.y() * X.y() * X.y(), -X.x(), 2.0,
      X.y() * X.z(), 0.3;
  return m;
}

TEST(SmoothFit, ReproducesPolynomialsUpToItsDegree) {
  const auto X = lattice();
  std::vector<uint16_t> object(X.size(), 0);
  std::vector<Mat3> field;
  for (const Vec3& p : X) field.push_back(smooth_field(p));
  nsf::ErrorSum exact, low;
  nsf::SmoothFit(X, object, 4).add_residual(field, exact);
  nsf::SmoothFit(X, object, 1).add_residual(field, low);
  EXPECT_LT(exact.relative(), 1e-9);
  EXPECT_GT(low.relative(), 1e-3);  // degree 1 cannot fit X_y⁴ or X_x X_z²
}

TEST(SmoothFit, LeavesParticleScaleNoiseAsItsResidual) {
  const auto X = lattice();
  // Two objects: each gets its own polynomial, so a jump between them costs nothing.
  std::vector<uint16_t> object;
  for (const Vec3& p : X) object.push_back(p.x() < 0.5 ? 0 : 1);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.2);
  std::vector<Mat3> field;
  double noise_sq = 0, field_sq = 0;
  for (size_t p = 0; p < X.size(); ++p) {
    Mat3 n;
    for (int k = 0; k < 9; ++k) n(k / 3, k % 3) = noise(rng);
    field.push_back(smooth_field(X[p]) + (object[p] ? 5.0 : 0.0) * Mat3::Identity() + n);
    noise_sq += n.squaredNorm(), field_sq += field.back().squaredNorm();
  }
  nsf::ErrorSum sum;
  nsf::SmoothFit(X, object, 4).add_residual(field, sum);
  // Least squares removes the noise's projection on 2 × 35 monomials out of 4096 points: the
  // residual is the noise, to within √(1 − 70/4096) and sampling error.
  const double noise_share = std::sqrt(noise_sq / field_sq);
  EXPECT_NEAR(sum.relative(), noise_share, 0.03 * noise_share);
}

TEST(GridForceError, IsZeroForTheSameStressAndScalesLinearly) {
  const auto x = lattice();
  const std::vector<double> volume(x.size(), 0.025 * 0.025 * 0.025);
  std::vector<Mat3> tau;
  for (const Vec3& p : x) tau.push_back(smooth_field(p));
  std::vector<Mat3> scaled = tau;
  for (Mat3& t : scaled) t *= 1.3;
  nsf::ErrorSum same, off;
  nsf::add_grid_force_error(x, volume, tau, tau, Vec3::Zero(), 0.05, same);
  nsf::add_grid_force_error(x, volume, scaled, tau, Vec3::Zero(), 0.05, off);
  EXPECT_EQ(same.err, 0.0);
  EXPECT_GT(same.ref, 0.0);
  EXPECT_NEAR(off.relative(), 0.3, 1e-12);  // forces are linear in τ
}

TEST(GridForceError, OneParticleOnANodeByHand) {
  // A particle on a node: weights (1/8, 3/4, 1/8) per axis at offsets (−Δx, 0, Δx), so with τ = I
  // and V⁰ = 1, f_i = −(4/Δx²) w_i (x_i − x_p) and
  // Σ‖f_i‖² = (16/Δx⁴) · 3 · (Σ_a w_a² d_a²) · (Σ_a w_a²)² = (16/Δx²) · 3 · (1/32) · (19/32)².
  const double dx = 0.05;
  const std::vector<Vec3> x = {Vec3(0.5, 0.5, 0.5)};
  const std::vector<double> volume = {1.0};
  const std::vector<Mat3> I = {Mat3::Identity()}, zero = {Mat3::Zero()};
  nsf::ErrorSum sum;
  nsf::add_grid_force_error(x, volume, zero, I, Vec3::Zero(), dx, sum);
  const double expected = 16.0 / (dx * dx) * 3.0 / 32.0 * (19.0 / 32.0) * (19.0 / 32.0);
  EXPECT_NEAR(sum.ref, expected, 1e-9 * expected);
  EXPECT_NEAR(sum.err, expected, 1e-9 * expected);
  EXPECT_DOUBLE_EQ(sum.relative(), 1.0);
}

TEST(GridForceError, MismatchedSizesAreAnError) {
  const auto x = lattice();
  const std::vector<double> volume(x.size(), 1.0);
  const std::vector<Mat3> tau(x.size() - 1, Mat3::Identity());
  nsf::ErrorSum sum;
  EXPECT_THROW(nsf::add_grid_force_error(x, volume, tau, tau, Vec3::Zero(), 0.05, sum),
               std::exception);
}

}  // namespace
