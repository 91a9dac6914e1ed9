// A body's rigid motion fitted to its particles (core/body_motion.h): exact for a rigid motion,
// the polar factor for a deformed one, ω from the particles' velocities.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "core/body_motion.h"
#include "core/error.h"
#include "random_matrices.h"

namespace {

using nsf::Mat3;
using nsf::Vec3;

struct Body {
  std::vector<Vec3> X, x, v;
  std::vector<double> mass;
  std::vector<uint32_t> all;
  Vec3 c0 = Vec3::Zero();
};

// 50 particles of unequal mass in a lumpy blob about (0.3, 0.2, 0.1).
Body blob(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-0.1, 0.1), m(0.5, 2.0);
  Body b;
  double M = 0;
  for (uint32_t p = 0; p < 50; ++p) {
    b.X.push_back(Vec3(0.3 + u(rng), 0.2 + 0.5 * u(rng), 0.1 + 0.3 * u(rng)));
    b.mass.push_back(m(rng));
    b.all.push_back(p);
    b.c0 += b.mass.back() * b.X.back();
    M += b.mass.back();
  }
  b.c0 /= M;
  return b;
}

TEST(BodyMotion, ARigidMotionIsRecoveredExactly) {
  std::mt19937_64 rng(7);
  Body b = blob(rng);
  const Mat3 R = nsf::testing::random_rotation(rng);
  const Vec3 t(0.05, -0.3, 0.2), w(1.5, -4.0, 2.5), u(0.7, 0.1, -0.2);
  for (const Vec3& X : b.X) {
    const Vec3 r = R * (X - b.c0);
    b.x.push_back(r + b.c0 + t);
    b.v.push_back(u + w.cross(r));
  }
  const nsf::BodyMotion m = nsf::fit_body_motion(b.X, b.x, b.v, b.mass, b.all);
  EXPECT_LT((m.rotation - R).norm(), 1e-12);
  EXPECT_LT((m.centre - (b.c0 + t)).norm(), 1e-14);
  EXPECT_LT((m.velocity - u).norm(), 1e-13);
  EXPECT_LT((m.angular_velocity - w).norm(), 1e-11);
  EXPECT_LT(m.rms_misfit, 1e-13);
}

// A turned stretch: no rotation fits better than the fit's (Kabsch's is the least-squares
// optimum), the misfit reported is the one at it, and it is near the stretch's own rotation.
TEST(BodyMotion, ADeformedBodyTakesTheBestFittingRotationAndReportsItsMisfit) {
  std::mt19937_64 rng(8);
  Body b = blob(rng);
  const Mat3 R = nsf::testing::random_rotation(rng);
  Mat3 S = Mat3::Identity();
  S(0, 0) = 1.2, S(1, 1) = 0.9, S(0, 1) = S(1, 0) = 0.05;
  for (const Vec3& X : b.X) b.x.push_back(R * S * (X - b.c0) + b.c0);
  const nsf::BodyMotion m = nsf::fit_body_motion(b.X, b.x, {}, b.mass, b.all);
  const auto rms = [&](const Mat3& Q) {
    double sum = 0, M = 0;
    for (size_t p = 0; p < b.X.size(); ++p) {
      sum += b.mass[p] * (Q * (b.X[p] - b.c0) + b.c0 - b.x[p]).squaredNorm();
      M += b.mass[p];
    }
    return std::sqrt(sum / M);
  };
  EXPECT_NEAR(m.rms_misfit, rms(m.rotation), 1e-15);
  EXPECT_GT(m.rms_misfit, 1e-3);
  EXPECT_LT(m.rms_misfit, rms(R));
  EXPECT_NEAR(m.rotation.determinant(), 1.0, 1e-12);
  for (int k = 0; k < 3; ++k)
    for (double h : {-1e-3, 1e-3}) {
      const Mat3 turn = Eigen::AngleAxisd(h, Vec3::Unit(k)).toRotationMatrix();
      EXPECT_GT(rms(turn * m.rotation), m.rms_misfit) << k << " " << h;
    }
  EXPECT_LT((m.rotation - R).norm(), 0.1);
  EXPECT_EQ(m.angular_velocity, Vec3::Zero());
}

// Only the members count; a body on a line has no ω along it and one particle none at all.
TEST(BodyMotion, MembersLinesAndSinglePointsAreHandled) {
  std::vector<Vec3> X = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(5, 5, 5)};
  std::vector<Vec3> x = X, v(4, Vec3::Zero());
  for (int p = 0; p < 3; ++p) v[size_t(p)] = Vec3(0, 0, 3.0 * (p - 1));  // ω = (0, −3, 0)
  v[3] = Vec3(100, 0, 0);
  const std::vector<double> mass(4, 1.0);
  const nsf::BodyMotion line = nsf::fit_body_motion(X, x, v, mass, {0, 1, 2});
  EXPECT_LT((line.angular_velocity - Vec3(0, -3, 0)).norm(), 1e-12);
  EXPECT_LT(line.velocity.norm(), 1e-15);
  EXPECT_LT((line.centre - Vec3(1, 0, 0)).norm(), 1e-15);
  const nsf::BodyMotion one = nsf::fit_body_motion(X, x, v, mass, {3});
  EXPECT_EQ(one.rotation, Mat3::Identity());
  EXPECT_EQ(one.velocity, Vec3(100, 0, 0));
  EXPECT_EQ(one.angular_velocity, Vec3::Zero());
  EXPECT_THROW(nsf::fit_body_motion(X, x, v, mass, {}), nsf::Error);
  EXPECT_THROW(nsf::fit_body_motion(X, x, v, mass, {4}), nsf::Error);
  EXPECT_THROW(nsf::fit_body_motion(X, x, v, {1.0}, {0}), nsf::Error);
  EXPECT_THROW(nsf::fit_body_motion(X, x, v, std::vector<double>(4, 0.0), {0, 1}), nsf::Error);
}

}  // namespace
