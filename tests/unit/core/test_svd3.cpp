#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "core/svd3.h"
#include "random_matrices.h"

namespace {

using nsf::Mat3;
using nsf::Vec3;

using nsf::testing::gaussian;
using nsf::testing::random_rotation;

Mat3 with_singular_values(std::mt19937_64& rng, const Vec3& s) {
  return random_rotation(rng) * s.asDiagonal() * random_rotation(rng).transpose();
}

// Checks every property of the convention on one matrix; returns a description of the first
// failure (empty when all hold) so the caller can report which case broke.
std::string check_svd(const Mat3& F) {
  Mat3 U, V;
  Vec3 s;
  nsf::svd3(F, U, s, V);
  const double scale = F.norm();
  const double rec = (U * s.asDiagonal() * V.transpose() - F).norm();
  if (!(rec <= 1e-12 * scale)) return "reconstruction error " + std::to_string(rec / scale);
  if (!((U.transpose() * U - Mat3::Identity()).norm() <= 1e-13)) return "U not orthonormal";
  if (!((V.transpose() * V - Mat3::Identity()).norm() <= 1e-13)) return "V not orthonormal";
  if (!(std::abs(U.determinant() - 1.0) <= 1e-13)) return "det U != 1";
  if (!(std::abs(V.determinant() - 1.0) <= 1e-13)) return "det V != 1";
  const double slack = 1e-14 * scale;
  if (!(s[0] >= 0 && s[1] >= 0)) return "negative leading singular value";
  if (!(s[0] + slack >= s[1] && s[1] + slack >= std::abs(s[2]))) return "not sorted";
  // The sign of σ2 must be that of det F whenever det F is clearly nonzero.
  const double det = F.determinant();
  if (std::abs(det) > 1e-10 * scale * scale * scale && (det > 0) != (s[2] > 0))
    return "sign of sigma2 disagrees with det F";
  // Magnitudes against Eigen's reference SVD.
  Eigen::JacobiSVD<Mat3> ref(F);
  Vec3 abs_s = s.cwiseAbs();
  if (!((abs_s - ref.singularValues()).norm() <= 1e-12 * scale)) return "singular values differ";
  return "";
}

struct Family {
  const char* name;
  std::function<Mat3(std::mt19937_64&)> make;
};

TEST(Svd3, ReconstructsThousandsOfHardMatrices) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const std::vector<Family> families = {
      {"gaussian", gaussian},
      {"near rotation",
       [&](std::mt19937_64& r) {
         return Mat3(random_rotation(r) * (Mat3::Identity() + 1e-3 * gaussian(r)));
       }},
      {"inverted",
       [&](std::mt19937_64& r) { return Mat3(gaussian(r) * Vec3(1, 1, -1).asDiagonal()); }},
      {"triple repeated",
       [&](std::mt19937_64& r) { return with_singular_values(r, Vec3(2, 2, 2)); }},
      {"double repeated",
       [&](std::mt19937_64& r) { return with_singular_values(r, Vec3(3, 1, 1)); }},
      {"repeated inverted",
       [&](std::mt19937_64& r) { return with_singular_values(r, Vec3(1, 1, -1)); }},
      {"nearly repeated",
       [&](std::mt19937_64& r) { return with_singular_values(r, Vec3(1 + 1e-14, 1, 1 - 1e-14)); }},
      {"rank two", [&](std::mt19937_64& r) { return with_singular_values(r, Vec3(2, 0.5, 0)); }},
      {"rank one", [&](std::mt19937_64& r) { return with_singular_values(r, Vec3(1, 0, 0)); }},
      {"rank one outer",
       [&](std::mt19937_64& r) {
         Vec3 a(u(r), u(r), u(r)), b(u(r), u(r), u(r));
         return Mat3(a * b.transpose());
       }},
      {"ill conditioned",
       [&](std::mt19937_64& r) { return with_singular_values(r, Vec3(1, 1e-8, 1e-16)); }},
      {"spread", [&](std::mt19937_64& r) { return with_singular_values(r, Vec3(1e6, 1, 1e-6)); }},
      {"tiny", [&](std::mt19937_64& r) { return Mat3(1e-200 * gaussian(r)); }},
      {"huge", [&](std::mt19937_64& r) { return Mat3(1e200 * gaussian(r)); }},
      {"subnormal", [&](std::mt19937_64& r) { return Mat3(1e-310 * gaussian(r)); }},
      {"sparse integer",
       [&](std::mt19937_64& r) {
         std::uniform_int_distribution<int> k(-1, 1);
         Mat3 A;
         for (int i = 0; i < 9; ++i) A.data()[i] = k(r);
         return A;
       }},
      {"signed permutation",
       [&](std::mt19937_64& r) {
         std::uniform_int_distribution<int> k(0, 5);
         Mat3 P = Mat3::Zero();
         int perm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
         int p = k(r);
         for (int i = 0; i < 3; ++i) P(i, perm[p][i]) = u(r) < 0 ? -1.0 : 1.0;
         return P;
       }},
  };
  std::mt19937_64 rng(12345);
  int checked = 0;
  for (const auto& fam : families) {
    for (int i = 0; i < 400; ++i, ++checked) {
      Mat3 F = fam.make(rng);
      std::string err = check_svd(F);
      ASSERT_TRUE(err.empty()) << fam.name << " #" << i << ": " << err << "\nF =\n" << F;
    }
  }
  EXPECT_GT(checked, 6000);
}

TEST(Svd3, ExactCases) {
  Mat3 U, V;
  Vec3 s;
  nsf::svd3(Mat3::Zero(), U, s, V);
  EXPECT_EQ(s, Vec3::Zero());
  EXPECT_EQ(U, Mat3::Identity());

  nsf::svd3(Mat3::Identity(), U, s, V);
  EXPECT_EQ(s, Vec3::Ones());
  EXPECT_NEAR((U * V.transpose() - Mat3::Identity()).norm(), 0.0, 1e-15);

  Mat3 F = Vec3(0.9, 1.1, 1.0).asDiagonal();
  nsf::svd3(F, U, s, V);
  EXPECT_NEAR((s - Vec3(1.1, 1.0, 0.9)).norm(), 0.0, 1e-15);

  nsf::svd3(-Mat3::Identity(), U, s, V);  // det −1: two of the signs fold into the rotations
  EXPECT_NEAR((s - Vec3(1, 1, -1)).norm(), 0.0, 1e-15);
}

TEST(Svd3, NonFiniteInputGivesNaN) {
  Mat3 F = Mat3::Identity();
  F(1, 2) = std::numeric_limits<double>::quiet_NaN();
  Mat3 U, V;
  Vec3 s;
  nsf::svd3(F, U, s, V);
  EXPECT_TRUE(std::isnan(s[0]));
  F(1, 2) = std::numeric_limits<double>::infinity();
  nsf::svd3(F, U, s, V);
  EXPECT_TRUE(std::isnan(s[0]));
}

TEST(Svd3, PolarOfInvertedMatrixKeepsProperRotation) {
  std::mt19937_64 rng(7);
  for (int i = 0; i < 200; ++i) {
    Mat3 F = gaussian(rng);
    Mat3 R, S;
    nsf::polar3(F, R, S);
    EXPECT_NEAR((R * S - F).norm(), 0.0, 1e-12 * F.norm());
    EXPECT_NEAR(R.determinant(), 1.0, 1e-13);
    EXPECT_NEAR((S - S.transpose()).norm(), 0.0, 1e-13 * F.norm());
    // S is definite iff F is not inverted.
    Eigen::SelfAdjointEigenSolver<Mat3> eig(S);
    EXPECT_EQ(eig.eigenvalues().minCoeff() < 0, F.determinant() < 0);
  }
}

}  // namespace
