#include "io/collider_raycast.h"

#include <algorithm>
#include <cmath>

namespace nsf {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The interval of t for which o + t·d lies in the slab |p| <= half (along one axis).
bool slab(double o, double d, double half, double& t0, double& t1) {
  if (std::abs(d) < 1e-12) {
    t0 = -kInf, t1 = kInf;
    return std::abs(o) <= half;
  }
  t0 = (-half - o) / d;
  t1 = (half - o) / d;
  if (t0 > t1) std::swap(t0, t1);
  return true;
}

bool hit_box(const ColliderShape& s, const Vec3& o, const Vec3& d, ColliderHit& hit) {
  const Vec3 ob = s.rotation.transpose() * (o - s.center), db = s.rotation.transpose() * d;
  double enter = -kInf, exit = kInf;
  int face = -1;
  for (int a = 0; a < 3; ++a) {
    double t0, t1;
    if (!slab(ob[a], db[a], s.half[a], t0, t1)) return false;
    if (t0 > enter) enter = t0, face = a;
    exit = std::min(exit, t1);
  }
  if (face < 0 || enter > exit || enter <= 0) return false;
  const Vec3 p = ob + enter * db;
  Vec3 n = Vec3::Zero();
  n[face] = p[face] < 0 ? -1 : 1;
  double edge = kInf;
  for (int a = 0; a < 3; ++a)
    if (a != face) edge = std::min(edge, s.half[a] - std::abs(p[a]));
  hit.t = enter;
  hit.normal = s.rotation * n;
  hit.edge = std::max(edge, 0.0);
  return true;
}

bool hit_cylinder(const ColliderShape& s, const Vec3& o, const Vec3& d, ColliderHit& hit) {
  const Vec3 ob = s.rotation.transpose() * (o - s.center), db = s.rotation.transpose() * d;
  const int a = s.axis, i = (a + 1) % 3, j = (a + 2) % 3;
  const double r = s.radius, hh = 0.5 * s.height;
  // Side: |radial part of o + t·d| <= r.
  double side0 = -kInf, side1 = kInf;
  const double A = db[i] * db[i] + db[j] * db[j];
  const double B = 2 * (ob[i] * db[i] + ob[j] * db[j]);
  const double C = ob[i] * ob[i] + ob[j] * ob[j] - r * r;
  if (A < 1e-12) {
    if (C > 0) return false;
  } else {
    const double disc = B * B - 4 * A * C;
    if (disc < 0) return false;
    const double q = std::sqrt(disc);
    side0 = (-B - q) / (2 * A);
    side1 = (-B + q) / (2 * A);
  }
  double cap0, cap1;
  if (!slab(ob[a], db[a], hh, cap0, cap1)) return false;
  const double enter = std::max(side0, cap0), exit = std::min(side1, cap1);
  if (enter > exit || enter <= 0) return false;
  const Vec3 p = ob + enter * db;
  Vec3 n = Vec3::Zero();
  if (side0 >= cap0) {
    n[i] = p[i];
    n[j] = p[j];
    n /= std::max(n.norm(), 1e-300);
    // Distance to the rim, or to the side's silhouette: seen in the plane across the axis, a
    // ray meeting the surface at angle θ from its normal passes r·sin θ from the axis, so
    // r(1 − sin θ) inside the outline.
    const double dperp = std::sqrt(A);
    const double cos_in = std::clamp(-(n[i] * db[i] + n[j] * db[j]) / dperp, 0.0, 1.0);
    const double silhouette = r * (1 - std::sqrt(std::max(0.0, 1 - cos_in * cos_in)));
    hit.edge = std::min(hh - std::abs(p[a]), silhouette);
  } else {
    n[a] = p[a] < 0 ? -1 : 1;
    hit.edge = r - std::hypot(p[i], p[j]);
  }
  hit.t = enter;
  hit.normal = s.rotation * n;
  hit.edge = std::max(hit.edge, 0.0);
  return true;
}

}  // namespace

bool ray_enters_solid(const ColliderShape& s, const Vec3& o, const Vec3& d, ColliderHit& hit) {
  switch (s.kind) {
    case ColliderShape::Kind::Box:
      return hit_box(s, o, d, hit);
    case ColliderShape::Kind::Cylinder:
      return hit_cylinder(s, o, d, hit);
    case ColliderShape::Kind::Plane:
      return false;
  }
  return false;
}

}  // namespace nsf
