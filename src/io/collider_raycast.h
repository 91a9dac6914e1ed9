#pragma once
// Where a ray meets a solid collider (box or cylinder), in closed form in the collider's own
// frame. Used to draw colliders and to cast their shadows on the ground.
#include <limits>

#include "core/types.h"
#include "io/collider_shapes.h"

namespace nsf {

// Where a ray enters a solid: distance t along the unit direction, outward normal (world), and
// how far the entry point is from the nearest edge or silhouette (world units), for outlines.
struct ColliderHit {
  double t = std::numeric_limits<double>::infinity();
  Vec3 normal = Vec3::UnitY();
  double edge = std::numeric_limits<double>::infinity();
};

// Only entries in front of the origin (t > 0) count: from inside a solid there is nothing
// sensible to draw. Planes are no solids here: false.
bool ray_enters_solid(const ColliderShape& s, const Vec3& o, const Vec3& d, ColliderHit& hit);

}  // namespace nsf
