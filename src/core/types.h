#pragma once
// Basic numeric types. The full-order engine runs in double precision (the paper's data are
// double).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

namespace nsf {

using Real = double;
using Vec3 = Eigen::Matrix<double, 3, 1>;
using Mat3 = Eigen::Matrix<double, 3, 3>;
using Vec3i = Eigen::Matrix<int, 3, 1>;

}  // namespace nsf
