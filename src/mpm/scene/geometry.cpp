#include "mpm/scene/geometry.h"

#include <algorithm>

#include "core/sdf.h"

namespace nsf {
namespace {

class Box : public Shape {
 public:
  Box(const Vec3& lo, const Vec3& hi) : c_(0.5 * (lo + hi)), half_(0.5 * (hi - lo)) {}
  double sdf(const Vec3& p) const override { return sdf::box(p - c_, half_); }
  Aabb bounds() const override { return {c_ - half_, c_ + half_}; }

 private:
  Vec3 c_, half_;
};

class Sphere : public Shape {
 public:
  Sphere(const Vec3& c, double r) : c_(c), r_(r) {}
  double sdf(const Vec3& p) const override { return sdf::sphere(p - c_, r_); }
  Aabb bounds() const override { return {(c_.array() - r_).matrix(), (c_.array() + r_).matrix()}; }

 private:
  Vec3 c_;
  double r_;
};

class Cylinder : public Shape {
 public:
  Cylinder(const Vec3& c, double r, double h, int axis) : c_(c), r_(r), h_(h), axis_(axis) {}
  double sdf(const Vec3& p) const override { return sdf::cylinder(p - c_, r_, h_, axis_); }
  Aabb bounds() const override {
    Vec3 half = Vec3::Constant(r_);
    half[axis_] = 0.5 * h_;
    return {c_ - half, c_ + half};
  }

 private:
  Vec3 c_;
  double r_, h_;
  int axis_;
};

class Capsule : public Shape {
 public:
  Capsule(const Vec3& a, const Vec3& b, double r) : a_(a), b_(b), r_(r) {}
  double sdf(const Vec3& p) const override { return sdf::capsule(p, a_, b_, r_); }
  Aabb bounds() const override {
    return {(a_.cwiseMin(b_).array() - r_).matrix(), (a_.cwiseMax(b_).array() + r_).matrix()};
  }

 private:
  Vec3 a_, b_;
  double r_;
};

class Torus : public Shape {
 public:
  Torus(const Vec3& c, double R, double r, int axis) : c_(c), R_(R), r_(r), axis_(axis) {}
  double sdf(const Vec3& p) const override { return sdf::torus(p - c_, R_, r_, axis_); }
  Aabb bounds() const override {
    Vec3 half = Vec3::Constant(R_ + r_);
    half[axis_] = r_;
    return {c_ - half, c_ + half};
  }

 private:
  Vec3 c_;
  double R_, r_;
  int axis_;
};

class Csg : public Shape {
 public:
  Csg(CsgOp op, std::vector<ShapePtr> children) : op_(op), children_(std::move(children)) {}

  double sdf(const Vec3& p) const override {
    double d = children_[0]->sdf(p);
    for (size_t i = 1; i < children_.size(); ++i) {
      double di = children_[i]->sdf(p);
      switch (op_) {
        case CsgOp::Union:
          d = std::min(d, di);
          break;
        case CsgOp::Intersection:
          d = std::max(d, di);
          break;
        case CsgOp::Difference:
          d = std::max(d, -di);
          break;
      }
    }
    return d;
  }

  Aabb bounds() const override {
    Aabb b = children_[0]->bounds();
    for (size_t i = 1; i < children_.size(); ++i) {
      Aabb bi = children_[i]->bounds();
      if (op_ == CsgOp::Union) {
        b.lo = b.lo.cwiseMin(bi.lo);
        b.hi = b.hi.cwiseMax(bi.hi);
      } else if (op_ == CsgOp::Intersection) {
        b.lo = b.lo.cwiseMax(bi.lo);
        b.hi = b.hi.cwiseMin(bi.hi);
      }  // a difference never grows beyond its first child
    }
    return b;
  }

 private:
  CsgOp op_;
  std::vector<ShapePtr> children_;
};

class Transformed : public Shape {
 public:
  Transformed(ShapePtr child, const Vec3& t, const Mat3& R, const Vec3& s)
      : child_(std::move(child)), t_(t), R_(R), s_(s), min_scale_(s.minCoeff()) {}

  double sdf(const Vec3& p) const override {
    Vec3 local = (R_.transpose() * (p - t_)).cwiseQuotient(s_);
    // Scaling the child's distance by the smallest factor keeps it a lower bound on the true
    // distance; the sign (all that sampling needs) is exact.
    return child_->sdf(local) * min_scale_;
  }

  Aabb bounds() const override {
    Aabb cb = child_->bounds(), out;
    if (cb.empty()) return cb;
    for (int corner = 0; corner < 8; ++corner) {
      Vec3 q((corner & 1) ? cb.hi.x() : cb.lo.x(), (corner & 2) ? cb.hi.y() : cb.lo.y(),
             (corner & 4) ? cb.hi.z() : cb.lo.z());
      out.extend(t_ + R_ * q.cwiseProduct(s_));
    }
    return out;
  }

 private:
  ShapePtr child_;
  Vec3 t_;
  Mat3 R_;
  Vec3 s_;
  double min_scale_;
};

}  // namespace

ShapePtr make_box(const Vec3& lo, const Vec3& hi) {
  return std::make_unique<Box>(lo, hi);
}
ShapePtr make_sphere(const Vec3& c, double r) {
  return std::make_unique<Sphere>(c, r);
}
ShapePtr make_cylinder(const Vec3& c, double r, double h, int axis) {
  return std::make_unique<Cylinder>(c, r, h, axis);
}
ShapePtr make_capsule(const Vec3& a, const Vec3& b, double r) {
  return std::make_unique<Capsule>(a, b, r);
}
ShapePtr make_torus(const Vec3& c, double R, double r, int axis) {
  return std::make_unique<Torus>(c, R, r, axis);
}
ShapePtr make_csg(CsgOp op, std::vector<ShapePtr> children) {
  return std::make_unique<Csg>(op, std::move(children));
}
ShapePtr make_transformed(ShapePtr child, const Vec3& translate, const Mat3& rotation,
                          const Vec3& scale) {
  return std::make_unique<Transformed>(std::move(child), translate, rotation, scale);
}

}  // namespace nsf
