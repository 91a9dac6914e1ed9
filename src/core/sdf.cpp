#include "core/sdf.h"

#include <algorithm>
#include <cmath>

namespace nsf::sdf {
namespace {

double sign_or_plus(double x) {
  return x < 0 ? -1.0 : 1.0;
}

// 2D "box" distance (radial, axial) shared by the cylinder: both offsets are signed distances
// to the two bounding surfaces.
double rounded_max(double a, double b) {
  double outside = std::hypot(std::max(a, 0.0), std::max(b, 0.0));
  return outside + std::min(std::max(a, b), 0.0);
}

// Splits p into (radial vector in the plane normal to the axis, coordinate along the axis).
void split_axis(const Vec3& p, int axis, Vec3& radial, double& along) {
  along = p[axis];
  radial = p;
  radial[axis] = 0.0;
}

}  // namespace

double box(const Vec3& p, const Vec3& half) {
  Vec3 q = p.cwiseAbs() - half;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

Vec3 box_normal(const Vec3& p, const Vec3& half) {
  Vec3 q = p.cwiseAbs() - half;
  Vec3 n = Vec3::Zero();
  if (q.maxCoeff() > 0) {
    n = q.cwiseMax(0.0);
  } else {
    int a;
    q.maxCoeff(&a);
    n[a] = 1.0;
  }
  for (int i = 0; i < 3; ++i) n[i] *= sign_or_plus(p[i]);
  return n.normalized();
}

double sphere(const Vec3& p, double r) {
  return p.norm() - r;
}

double cylinder(const Vec3& p, double r, double h, int axis) {
  Vec3 radial;
  double along;
  split_axis(p, axis, radial, along);
  return rounded_max(radial.norm() - r, std::abs(along) - 0.5 * h);
}

Vec3 cylinder_normal(const Vec3& p, double r, double h, int axis) {
  Vec3 radial;
  double along;
  split_axis(p, axis, radial, along);
  double rn = radial.norm();
  double dr = rn - r, da = std::abs(along) - 0.5 * h;
  Vec3 er = Vec3::Zero();
  if (rn > 0) {
    er = radial / rn;
  } else {
    er[(axis + 1) % 3] = 1.0;  // on the axis every radial direction is as good
  }
  Vec3 ea = Vec3::Zero();
  ea[axis] = sign_or_plus(along);
  if (dr > 0 && da > 0) return (dr * er + da * ea).normalized();
  if (dr > 0) return er;
  if (da > 0) return ea;
  return dr > da ? er : ea;
}

double capsule(const Vec3& p, const Vec3& a, const Vec3& b, double r) {
  Vec3 ab = b - a;
  double len2 = ab.squaredNorm();
  double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm() - r;
}

double torus(const Vec3& p, double R, double r, int axis) {
  Vec3 radial;
  double along;
  split_axis(p, axis, radial, along);
  return std::hypot(radial.norm() - R, along) - r;
}

}  // namespace nsf::sdf
