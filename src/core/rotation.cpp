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

int axis_index(const std::string& name, const std::string& path) {
  if (name == "x") return 0;
  if (name == "y") return 1;
  if (name == "z") return 2;
  fail("scene: '", path, "' = \"", name, "\" is not an axis; use \"x\", \"y\" or \"z\"");
}

}  // namespace nsf
