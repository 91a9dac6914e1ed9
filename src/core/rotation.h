#pragma once
// Orientations as written in scenes. One convention everywhere (shapes, colliders, keyframes):
// "rotate_deg": [rx, ry, rz] are extrinsic rotations in degrees about the world x, then y, then z
// axis, i.e. R = Rz(rz) · Ry(ry) · Rx(rx).
#include <string>

#include "core/types.h"

namespace nsf {

Mat3 rotation_from_euler_deg(const Vec3& deg);

// The inverse: angles in degrees with ry in [−90, 90] (at ±90, rx = 0), so that
// rotation_from_euler_deg of them gives `rotation` back.
Vec3 euler_deg_from_rotation(const Mat3& rotation);

// Index 0/1/2 of an axis name "x"/"y"/"z"; throws nsf::Error naming `path` otherwise.
int axis_index(const std::string& name, const std::string& path);

}  // namespace nsf
