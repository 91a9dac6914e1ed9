#pragma once
// Solid shapes for scene objects and weak regions: primitives, CSG combinators and transforms,
// all answering a signed distance (negative inside). Sampling only needs the sign and a bounding
// box; the distance is exact for primitives and rigid transforms, and a bound for CSG and
// non-uniform scale.
#include <limits>
#include <memory>
#include <vector>

#include "core/types.h"

namespace nsf {

struct Aabb {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = Vec3::Constant(-std::numeric_limits<double>::infinity());
  bool empty() const { return (hi.array() < lo.array()).any(); }
  void extend(const Vec3& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
};

class Shape {
 public:
  virtual ~Shape() = default;
  virtual double sdf(const Vec3& p) const = 0;
  // Contains every point with sdf <= 0 (may be larger than the shape).
  virtual Aabb bounds() const = 0;
  bool contains(const Vec3& p) const { return sdf(p) <= 0.0; }
};

using ShapePtr = std::unique_ptr<Shape>;

ShapePtr make_box(const Vec3& lo, const Vec3& hi);
ShapePtr make_sphere(const Vec3& center, double radius);
ShapePtr make_cylinder(const Vec3& center, double radius, double height, int axis);
ShapePtr make_capsule(const Vec3& a, const Vec3& b, double radius);
ShapePtr make_torus(const Vec3& center, double major_radius, double minor_radius, int axis);

enum class CsgOp { Union, Intersection, Difference };
// Difference: the first child minus all the others.
ShapePtr make_csg(CsgOp op, std::vector<ShapePtr> children);

// World point = translate + R · (scale ⊙ local point).
ShapePtr make_transformed(ShapePtr child, const Vec3& translate, const Mat3& rotation,
                          const Vec3& scale);

}  // namespace nsf
