#pragma once
// Signed distances of primitives in their own frame (centred at the origin): negative inside,
// zero on the surface. Shared by the scene geometry (particle sampling) and the rigid colliders
// (which also need the outward normal). The normals are unit gradients of the distance; on a
// medial surface inside (equidistant from two faces) one of the faces is chosen.
#include "core/types.h"

namespace nsf::sdf {

double box(const Vec3& p, const Vec3& half);
Vec3 box_normal(const Vec3& p, const Vec3& half);

double sphere(const Vec3& p, double r);

// Cylinder of radius r and height h whose axis is `axis` (0, 1, 2).
double cylinder(const Vec3& p, double r, double h, int axis);
Vec3 cylinder_normal(const Vec3& p, double r, double h, int axis);

// Capsule: all points within r of the segment ab.
double capsule(const Vec3& p, const Vec3& a, const Vec3& b, double r);

// Torus whose symmetry axis is `axis`; the tube's centre circle has radius R, the tube radius r.
double torus(const Vec3& p, double R, double r, int axis);

}  // namespace nsf::sdf
