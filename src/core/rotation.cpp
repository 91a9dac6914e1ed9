#include "core/rotation.h"

#include <cmath>
#include <string>

#include "core/error.h"

namespace nsf {

Mat3 rotation_from_euler_deg(const Vec3& deg) {
  const Vec3 rad = deg * (M_PI / 180.0);
  return (Eigen::AngleAxisd(rad.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rad.y(), Vec3::UnitY()) *
          Eigen::AngleAxisd(rad.x(), Vec3::UnitX()))
      .toRotationMatrix();
}

Vec3 euler_deg_from_rotation(const Mat3& R) {
  // R = Rz·Ry·Rx: R(2,0) = −sin ry, R(2,1) = cos ry sin rx, R(1,0) = sin rz cos ry. cos ry from
  // the first column's other two entries keeps ry accurate near ±90°, where asin is not.
  const double cy = std::hypot(R(0, 0), R(1, 0));
  const double ry = std::atan2(-R(2, 0), cy);
  double rx = 0, rz = 0;
  if (cy > 1e-12) {
    rx = std::atan2(R(2, 1), R(2, 2));
    rz = std::atan2(R(1, 0), R(0, 0));
  } else {
    // Gimbal lock: only rz ∓ rx is defined; take rx = 0.
    rz = std::atan2(-R(0, 1), R(1, 1));
  }
  return Vec3(rx, ry, rz) * (180.0 / M_PI);
}

int axis_index(const std::string& name, const std::string& path) {
  if (name == "x") return 0;
  if (name == "y") return 1;
  if (name == "z") return 2;
  fail("scene: '", path, "' = \"", name, "\" is not an axis; use \"x\", \"y\" or \"z\"");
}

}  // namespace nsf
