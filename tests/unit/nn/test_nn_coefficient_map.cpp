// GCC 12 reports false -Wmaybe-uninitialized warnings from inside Eigen's AVX-512 kernels for
// dynamic-size products (in the intrinsics headers, not in this code).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

// The coefficient maps of a basis model (nn/rbf_map.h) and the latent velocity C's map reads
// (BasisDecoders::latent_velocity).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "core/error.h"
#include "nn/basis_decoders.h"
#include "nn/rbf_map.h"

namespace {

// n rows of d inputs spread over [-1, 2], in `groups` groups.
Eigen::MatrixXd rows(int n, int d, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 2.0);
  return Eigen::MatrixXd::NullaryExpr(n, d, [&] { return u(rng); });
}

std::vector<int> groups(int n, int count) {
  std::vector<int> g(size_t(n), 0);
  for (int i = 0; i < n; ++i) g[size_t(i)] = i % count;
  return g;
}

}  // namespace

// A thin-plate spline with its linear tail reproduces an affine function exactly, whatever the
// smoothing: the cross-validation sees no error and the map is exact between the rows too.
TEST(CoefficientMap, ReproducesAnAffineFunctionExactly) {
  const Eigen::MatrixXd x = rows(60, 3, 1);
  Eigen::MatrixXd A(3, 2);
  A << 1.0, -2.0, 0.5, 0.25, -3.0, 1.0;
  const Eigen::RowVector2d c0(0.7, -0.1);
  const Eigen::MatrixXd y = (x * A).rowwise() + c0;
  nsf::RbfFitReport report;
  const nsf::RbfMap m = nsf::fit_rbf(x, y, groups(60, 6), &report);
  EXPECT_EQ(report.folds, 6);
  EXPECT_LT(report.cv_error, 1e-18);
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(1.5, -0.5, 0.0)}) {
    const Eigen::VectorXd expect = A.transpose() * p + c0.transpose();
    EXPECT_LT((m(p) - expect).norm(), 1e-9 * (1 + expect.norm()));
  }
}

// A smooth function: the map holds its training rows to within the chosen smoothing, is close
// on rows it never saw, and the cross-validated error says how close.
TEST(CoefficientMap, InterpolatesASmoothFunctionAndReportsItsHeldOutError) {
  const auto f = [](const Eigen::VectorXd& p) {
    Eigen::VectorXd out(2);
    out << std::sin(p[0]) * std::cos(p[1]), std::exp(0.3 * p[1]) - p[0] * p[1];
    return out;
  };
  const Eigen::MatrixXd x = rows(300, 2, 2);
  Eigen::MatrixXd y(300, 2);
  for (int i = 0; i < 300; ++i) y.row(i) = f(x.row(i).transpose()).transpose();
  nsf::RbfFitReport report;
  const nsf::RbfMap m = nsf::fit_rbf(x, y, groups(300, 10), &report);
  EXPECT_LT(report.cv_error, 1e-4);
  const Eigen::MatrixXd probe = rows(50, 2, 3).cwiseMax(-0.9).cwiseMin(1.9);
  double err = 0, norm = 0;
  for (int i = 0; i < probe.rows(); ++i) {
    const Eigen::VectorXd p = probe.row(i).transpose();
    err += (m(p) - f(p)).squaredNorm(), norm += f(p).squaredNorm();
  }
  EXPECT_LT(std::sqrt(err / norm), 0.01);
}

// One training run that no other predicts (a slab that tore another way) must not choose the
// smoothing for the others: the error reported, and judged by, is the median run's, so it stays
// that of the smooth runs where a sum over the rows would be the odd run's.
TEST(CoefficientMap, OneUnpredictableRunDoesNotDecideTheSmoothing) {
  // Each run its own band of the first input (as each run has its μ), the fourth band the odd one.
  const Eigen::MatrixXd x = rows(320, 2, 6);
  std::vector<int> g(320);
  for (int i = 0; i < 320; ++i) g[size_t(i)] = std::min(7, int((x(i, 0) + 1.0) / 3.0 * 8));
  Eigen::MatrixXd y(320, 1);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 3.0);
  for (int i = 0; i < 320; ++i)
    y(i, 0) = g[size_t(i)] == 3 ? noise(rng) : std::sin(x(i, 0)) + 0.5 * x(i, 1) * x(i, 1);
  nsf::RbfFitReport report;
  nsf::fit_rbf(x, y, g, &report);
  EXPECT_LT(report.cv_error, 0.05);
  EXPECT_LT(report.smoothing, 1.0);
}

// ∂c/∂x against central differences, inside the training rows' box; outside it (past half a
// spread) the map holds the value at the box's face and its derivative across the face is zero.
TEST(CoefficientMap, JacobianMatchesFiniteDifferencesAndTheBoxHoldsOutsiders) {
  const Eigen::MatrixXd x = rows(80, 4, 4);
  Eigen::MatrixXd y(80, 3);
  for (int i = 0; i < 80; ++i)
    y.row(i) << std::sin(x(i, 0) + x(i, 3)), x(i, 1) * x(i, 2), std::cos(2 * x(i, 2));
  const nsf::RbfMap m = nsf::fit_rbf(x, y, groups(80, 4));
  Eigen::VectorXd p(4);
  p << 0.3, 0.9, -0.2, 1.1;
  Eigen::MatrixXd J;
  m(p, &J);
  ASSERT_EQ(J.rows(), 3);
  ASSERT_EQ(J.cols(), 4);
  const double h = 1e-6;
  for (int k = 0; k < 4; ++k) {
    const Eigen::VectorXd e = h * Eigen::VectorXd::Unit(4, k);
    const Eigen::VectorXd fd = (m(p + e) - m(p - e)) / (2 * h);
    EXPECT_LT((J.col(k) - fd).norm(), 1e-5 * (1 + fd.norm())) << "column " << k;
  }
  Eigen::VectorXd far = p, face = p;
  far[1] = 50.0;
  face[1] = m.shift[1] + m.scale[1] * (m.centers.col(1).maxCoeff() + 0.5);  // the box's margin
  EXPECT_LT((m(far) - m(face)).norm(), 1e-12 * (1 + m(face).norm()));
  m(far, &J);
  EXPECT_EQ(J.col(1).norm(), 0.0);
}

// A constant input (μ of a dataset without one) is no error, and bad rows are named.
TEST(CoefficientMap, ConstantInputsAreFineAndBadRowsAreNamed) {
  Eigen::MatrixXd x = rows(40, 3, 5);
  x.col(2).setConstant(0.1);  // not exactly its own mean in floating point
  const Eigen::MatrixXd y = x.col(0) * 2.0 - x.col(1);
  const nsf::RbfMap m = nsf::fit_rbf(x, y, groups(40, 4));
  Eigen::Vector3d p(0.5, 0.5, 0.1);
  EXPECT_NEAR(m(p)[0], 0.5, 1e-9);
  Eigen::MatrixXd bad = x;
  bad(3, 1) = std::nan("");
  EXPECT_THROW(nsf::fit_rbf(bad, y, groups(40, 4)), nsf::Error);
  EXPECT_THROW(nsf::fit_rbf(x.topRows(4), y.topRows(4), groups(4, 2)), nsf::Error);
  EXPECT_THROW(m(Eigen::Vector2d(0, 0)), nsf::Error);
}

// The latent velocity of particle velocities made by a known ż through g's tangent is that ż.
TEST(CoefficientMap, LatentVelocityRecoversTheLatentThatMadeTheVelocities) {
  std::mt19937 rng(6);
  std::normal_distribution<double> n(0.0, 0.5);
  const int P = 40, K = 6, r = 3;
  // Orthonormal modes over the particles' 3P components, stored per point (dim × K).
  const Eigen::MatrixXd Q = Eigen::MatrixXd::NullaryExpr(3 * P, K, [&] { return n(rng); })
                                .householderQr()
                                .householderQ() *
                            Eigen::MatrixXd::Identity(3 * P, K);
  nsf::BasisDecoders d;
  d.u.dim = 3, d.u.K = K, d.u.points = size_t(P);
  d.u.mean.assign(size_t(3 * P), 0.0f);
  for (int p = 0; p < P; ++p)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < K; ++k) d.u.modes.push_back(float(Q(3 * p + c, k)));
  const int sizes[] = {r, 8, K};
  for (int i = 0; i < 2; ++i) {
    d.u.net.W.push_back(
        Eigen::MatrixXd::NullaryExpr(sizes[i + 1], sizes[i], [&] { return n(rng); }));
    d.u.net.b.push_back(Eigen::VectorXd::NullaryExpr(sizes[i + 1], [&] { return n(rng); }));
  }
  d.u.net.in_shift = Eigen::VectorXd::Zero(r), d.u.net.in_scale = Eigen::VectorXd::Ones(r);
  d.u.net.out_scale = Eigen::VectorXd::Ones(K);
  Eigen::VectorXd z(r), zdot(r);
  z << 0.2, -0.3, 0.5;
  zdot << 1.5, -0.7, 0.2;
  Eigen::MatrixXd J;
  d.u.net(z, &J);
  const Eigen::VectorXd v = Q * (J * zdot);
  std::vector<float> vf(v.data(), v.data() + v.size());
  EXPECT_LT((d.latent_velocity(z, vf.data()) - zdot).norm(), 1e-4 * zdot.norm());
  // C's input without ż, where the model reads it, is an internal error, not a silent zero.
  d.affine_uses_velocity = true;
  EXPECT_THROW(d.affine_input(z, 1.0, nullptr), nsf::Error);
  EXPECT_EQ(d.affine_input(z, 1.0, &zdot).size(), 2 * r + 1);
}
