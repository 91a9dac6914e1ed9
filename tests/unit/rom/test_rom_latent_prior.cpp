// The latent prior (rom/inversion/latent_prior.h): distance to the surface the training runs'
// latents span, its Gauss–Newton terms, and the inversion held near it. GCC 12 reports false
// -Wmaybe-uninitialized warnings from inside Eigen's AVX-512 kernels for dynamic-size matrices (in
// the intrinsics headers, not in this code).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "error_matchers.h"
#include "rom/inversion/latent_prior.h"

namespace {

using Runs = std::vector<std::vector<Eigen::VectorXd>>;

// Three runs of four frames in r = 3: a wavy sheet, so that neighbouring triangles are not
// coplanar and the closest feature changes from place to place.
Runs wavy_runs() {
  Runs runs(3);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 4; ++i) {
      Eigen::VectorXd z(3);
      z << 2.0 * i, 1.0 * j, 0.3 * std::sin(1.3 * i + 0.7 * j) + 0.1 * i * j;
      runs[size_t(j)].push_back(z);
    }
  return runs;
}

// Each component's spread over the training latents (population standard deviation), as the
// model's norm_z holds it.
Eigen::VectorXd spread_of(const Runs& runs) {
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(runs[0][0].size()), sq = mean;
  double n = 0;
  for (const auto& run : runs)
    for (const auto& z : run) mean += z, n += 1;
  mean /= n;
  for (const auto& run : runs)
    for (const auto& z : run) sq += (z - mean).cwiseAbs2();
  return (sq / n).cwiseSqrt();
}

// Brute force: the smallest whitened squared distance to points sampled densely on every
// triangle of the (μ, t) grid.
double sampled_distance2(const Runs& runs, const Eigen::VectorXd& z) {
  const Eigen::VectorXd s = spread_of(runs);
  double best = INFINITY;
  const int n = 60;
  for (size_t j = 0; j + 1 < runs.size(); ++j)
    for (size_t i = 0; i + 1 < runs[0].size(); ++i) {
      const Eigen::VectorXd &a = runs[j][i], &b = runs[j + 1][i], &c = runs[j][i + 1],
                            &d = runs[j + 1][i + 1];
      for (int p = 0; p <= n; ++p)
        for (int q = 0; p + q <= n; ++q) {
          const double u = double(p) / n, v = double(q) / n;
          const Eigen::VectorXd x1 = a + u * (b - a) + v * (c - a);
          const Eigen::VectorXd x2 = d + u * (c - d) + v * (b - d);
          best = std::min(best, (z - x1).cwiseQuotient(s).squaredNorm());
          best = std::min(best, (z - x2).cwiseQuotient(s).squaredNorm());
        }
    }
  return best;
}

TEST(LatentPrior, DistanceIsTheWhitenedDistanceToTheTrainingRunsSurface) {
  const Runs runs = wavy_runs();
  const nsf::LatentPrior prior(runs, spread_of(runs));
  // On the surface: every training latent, and a point inside one of its triangles.
  for (const auto& run : runs)
    for (const auto& z : run) EXPECT_LT(prior.distance2(z), 1e-20);
  const Eigen::VectorXd inside = (runs[0][1] + runs[1][1] + runs[0][2]) / 3.0;
  EXPECT_LT(prior.distance2(inside), 1e-20);
  // Off it, anywhere (beyond the edges too): the brute-force minimum, which can only be larger.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.5, 7.5), v(-1.0, 3.0), w(-1.5, 1.5);
  for (int k = 0; k < 40; ++k) {
    Eigen::VectorXd z(3);
    z << u(rng), v(rng), w(rng);
    const double exact = prior.distance2(z), sampled = sampled_distance2(runs, z);
    EXPECT_LE(exact, sampled + 1e-12) << z.transpose();
    EXPECT_NEAR(std::sqrt(exact), std::sqrt(sampled), 0.02) << z.transpose();
  }
}

// The search skips triangles by their bounding balls: on a sweep-sized surface (12 runs of 33
// frames in r = 5, curled so that far-apart parts of it come close) it must still find the
// nearest, at points near the surface, between its folds and far from it.
TEST(LatentPrior, SkippingTrianglesByTheirBallsStillFindsTheNearest) {
  Runs runs(12);
  for (int j = 0; j < 12; ++j)
    for (int i = 0; i < 33; ++i) {
      const double t = 0.2 * i, m = 0.3 * j;
      Eigen::VectorXd z(5);
      z << std::cos(t) * (1 + m), std::sin(t) * (1 + m), 0.2 * t, m * std::sin(2 * t),
          0.1 * std::cos(3 * t + m);
      runs[size_t(j)].push_back(z);
    }
  const nsf::LatentPrior prior(runs, spread_of(runs));
  const Eigen::VectorXd s = spread_of(runs);
  // Every triangle's nearest point exactly, by a fine sampling of its parameters: the true
  // minimum can only be below any sampled distance, and close to the finest one.
  const auto sampled = [&](const Eigen::VectorXd& z) {
    double best = INFINITY;
    const int n = 12;
    for (size_t j = 0; j + 1 < runs.size(); ++j)
      for (size_t i = 0; i + 1 < runs[0].size(); ++i)
        for (int p = 0; p <= n; ++p)
          for (int q = 0; p + q <= n; ++q) {
            const double u = double(p) / n, v = double(q) / n;
            const Eigen::VectorXd &a = runs[j][i], &b = runs[j + 1][i], &c = runs[j][i + 1],
                                  &d = runs[j + 1][i + 1];
            best =
                std::min(best, (z - a - u * (b - a) - v * (c - a)).cwiseQuotient(s).squaredNorm());
            best =
                std::min(best, (z - d - u * (c - d) - v * (b - d)).cwiseQuotient(s).squaredNorm());
          }
    return best;
  };
  std::mt19937 rng(5);
  for (double scale : {0.05, 0.5, 3.0}) {
    std::normal_distribution<double> off(0.0, scale);
    std::uniform_int_distribution<size_t> pick_run(0, 11), pick_frame(0, 32);
    for (int k = 0; k < 15; ++k) {
      Eigen::VectorXd z = runs[pick_run(rng)][pick_frame(rng)];
      for (int m = 0; m < 5; ++m) z[m] += off(rng) * s[m];
      const double found = prior.distance2(z), bound = sampled(z);
      EXPECT_LE(found, bound + 1e-12) << z.transpose();
      EXPECT_NEAR(std::sqrt(found), std::sqrt(bound), 0.05) << z.transpose();
    }
  }
}

TEST(LatentPrior, DistanceIsInUnitsOfEachComponentsSpread) {
  Runs runs = wavy_runs();
  const nsf::LatentPrior prior(runs, spread_of(runs));
  Eigen::VectorXd z(3);
  z << 3.1, 0.4, 1.2;
  // Scaling a latent component (training latents, their spread and the query alike) changes
  // nothing.
  for (auto& run : runs)
    for (auto& q : run) q[2] *= 10.0;
  const nsf::LatentPrior scaled(runs, spread_of(runs));
  Eigen::VectorXd zs = z;
  zs[2] *= 10.0;
  EXPECT_NEAR(scaled.distance2(zs), prior.distance2(z), 1e-9 * prior.distance2(z));
  EXPECT_GT(prior.distance2(z), 0.1);
}

TEST(LatentPrior, GradientAndHessianAreTheSquaredDistancesHalvedDerivatives) {
  const nsf::LatentPrior prior(wavy_runs(), spread_of(wavy_runs()));
  // Points whose closest feature is a triangle's interior, an edge, and a corner of the sheet.
  std::vector<Eigen::VectorXd> points(3, Eigen::VectorXd(3));
  points[0] << 3.1, 0.6, 0.9;
  points[1] << 2.9, -0.8, 0.5;
  points[2] << -1.0, -1.0, 0.7;
  for (const Eigen::VectorXd& z : points) {
    const nsf::LatentPrior::Nearest n = prior.nearest(z);
    EXPECT_NEAR(n.distance2, prior.distance2(z), 1e-12);
    ASSERT_GT(n.distance2, 1e-3);
    const double h = 1e-5;
    for (int k = 0; k < 3; ++k) {
      Eigen::VectorXd zp = z, zm = z;
      zp[k] += h, zm[k] -= h;
      const double fd = (prior.distance2(zp) - prior.distance2(zm)) / (2 * h);
      EXPECT_NEAR(n.gradient[k], 0.5 * fd, 1e-6 * (1 + std::abs(fd))) << z.transpose();
      // The Hessian is that of the closest feature's plane: exact while that feature stays the
      // closest, which it does over so small a step.
      const Eigen::VectorXd dg =
          (prior.nearest(zp).gradient - prior.nearest(zm).gradient) / (2 * h);
      for (int m = 0; m < 3; ++m) EXPECT_NEAR(n.hessian(m, k), dg[m], 1e-5) << z.transpose();
    }
  }
}

TEST(LatentPrior, OneRunIsItsCurveAndNoLatentsAreAClearError) {
  Runs one(1);
  for (int i = 0; i < 3; ++i) {
    Eigen::VectorXd z(2);
    z << double(i), double(i % 2);
    one[0].push_back(z);
  }
  const nsf::LatentPrior curve(one, spread_of(one));
  Eigen::VectorXd mid(2);
  mid << 0.5, 0.5;  // on the first segment
  EXPECT_LT(curve.distance2(mid), 1e-20);
  // Off it: the whitened distance to the nearer of its two segments, sampled finely.
  Eigen::VectorXd off(2);
  off << 1.0, 0.0;
  const Eigen::VectorXd s = spread_of(one);
  double expected = INFINITY;
  for (int seg = 0; seg < 2; ++seg)
    for (int k = 0; k <= 100000; ++k) {
      const Eigen::VectorXd p = one[0][seg] + (k / 1e5) * (one[0][seg + 1] - one[0][seg]);
      expected = std::min(expected, (off - p).cwiseQuotient(s).squaredNorm());
    }
  EXPECT_NEAR(curve.distance2(off), expected, 1e-8);
  EXPECT_GT(expected, 0.1);
  nsf::testing::expect_contains(
      nsf::testing::error_of([] { nsf::LatentPrior(Runs{}, Eigen::VectorXd::Ones(2)); }),
      "no training latents");
  nsf::testing::expect_contains(
      nsf::testing::error_of([&] { nsf::LatentPrior(one, Eigen::Vector2d(1.0, 0.0)); }),
      "positive");
  nsf::testing::expect_contains(
      nsf::testing::error_of([&] { nsf::LatentPrior(one, Eigen::VectorXd::Ones(3)); }), "positive");
}

}  // namespace
