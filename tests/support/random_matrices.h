#pragma once
// Seeded random 3x3 matrices for the SVD and polar tests.
#include <random>

#include "core/types.h"

namespace nsf::testing {

inline Mat3 random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  return q.normalized().toRotationMatrix();
}

inline Mat3 gaussian(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Mat3 A;
  for (int i = 0; i < 9; ++i) A.data()[i] = n(rng);
  return A;
}

}  // namespace nsf::testing
