// The fast polar rotation must agree with the robust SVD's R = U Vᵀ wherever it accepts F, and
// must decline (so callers fall back to svd3) wherever the MPM convention needs the SVD.
#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "core/polar3.h"
#include "core/svd3.h"
#include "random_matrices.h"

namespace {

using nsf::Mat3;
using nsf::Vec3;

using nsf::testing::gaussian;
using nsf::testing::random_rotation;

TEST(Polar3, MatchesSvdRotationOnMpmLikeMatrices) {
  std::mt19937_64 rng(7);
  int accepted = 0;
  for (double strain : {0.0, 1e-6, 1e-3, 1e-2, 0.1, 0.3}) {
    for (int i = 0; i < 500; ++i) {
      const Mat3 F = random_rotation(rng) * (Mat3::Identity() + strain * gaussian(rng));
      Mat3 R;
      double J;
      if (!nsf::fast_polar_rotation(F, R, J)) {
        EXPECT_GE(strain, 0.1) << "declined a near-rotation F:\n" << F;
        continue;
      }
      ++accepted;
      Mat3 U, V;
      Vec3 s;
      nsf::svd3(F, U, s, V);
      EXPECT_LT((R - U * V.transpose()).norm(), 1e-13) << "strain " << strain << "\nF =\n" << F;
      EXPECT_LT((R.transpose() * R - Mat3::Identity()).norm(), 1e-14);
      EXPECT_NEAR(J, F.determinant(), 1e-15 * std::abs(F.determinant()));
    }
  }
  EXPECT_GT(accepted, 2800);
}

TEST(Polar3, DeclinesWhereTheSvdIsNeeded) {
  Mat3 R;
  double J;
  // Inverted: Newton would converge to an improper orthogonal matrix.
  EXPECT_FALSE(nsf::fast_polar_rotation(Vec3(1.2, 1.0, -0.8).asDiagonal(), R, J));
  EXPECT_FALSE(nsf::fast_polar_rotation(Mat3::Zero(), R, J));
  EXPECT_FALSE(nsf::fast_polar_rotation(Vec3(1, 1, 0).asDiagonal(), R, J));       // singular
  EXPECT_FALSE(nsf::fast_polar_rotation(Vec3(1e3, 1, 1e-3).asDiagonal(), R, J));  // distorted
  EXPECT_FALSE(nsf::fast_polar_rotation(1e-200 * Mat3::Identity(), R, J));        // tiny
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(nsf::fast_polar_rotation(Mat3::Constant(nan), R, J));
  Mat3 inf = Mat3::Identity();
  inf(0, 1) = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(nsf::fast_polar_rotation(inf, R, J));
}

TEST(Polar3, ExactCases) {
  Mat3 R;
  double J = 0;
  ASSERT_TRUE(nsf::fast_polar_rotation(Mat3::Identity(), R, J));
  EXPECT_EQ(R, Mat3::Identity());
  EXPECT_EQ(J, 1.0);
  ASSERT_TRUE(nsf::fast_polar_rotation(Vec3(1.1, 0.9, 1.0).asDiagonal(), R, J));
  EXPECT_LT((R - Mat3::Identity()).norm(), 1e-15);
}

}  // namespace
