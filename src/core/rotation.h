#pragma once
// Orientations as written in scenes. One convention everywhere (shapes, colliders, keyframes):
// "rotate_deg": [rx, ry, rz] are extrinsic rotations in degrees about the world x, then y, then z
// axis, i.e. R = Rz(rz) · Ry(ry) · Rx(rx).
#include <string>

#include "core/types.h"

namespace nsf {

Mat3 rotation_from_euler_deg(const Vec3& deg);

// Index 0/1/2 of an axis name "x"/"y"/"z"; throws nsf::Error naming `path` otherwise.
int axis_index(const std::string& name, const std::string& path);

}  // namespace nsf
