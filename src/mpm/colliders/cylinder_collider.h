#pragma once
// A solid rigid cylinder (rolling pin, pillar, toothbrush handle), optionally rotated and moving.
#include <nlohmann/json.hpp>
#include <string>

#include "core/sdf.h"
#include "mpm/colliders/rigid_collider.h"

namespace nsf {

class CylinderCollider : public RigidCollider {
 public:
  CylinderCollider(double radius, double height, int axis, ContactRule contact, RigidMotion motion)
      : RigidCollider(contact, std::move(motion)), r_(radius), h_(height), axis_(axis) {}
  static std::unique_ptr<Collider> parse(const nlohmann::json& j, const std::string& path);
  std::string type() const override { return "cylinder"; }
  // Body-frame dimensions, for drawing.
  double radius() const { return r_; }
  double height() const { return h_; }
  int axis() const { return axis_; }

 protected:
  double body_sdf(const Vec3& p) const override { return sdf::cylinder(p, r_, h_, axis_); }
  Vec3 body_normal(const Vec3& p) const override { return sdf::cylinder_normal(p, r_, h_, axis_); }

 private:
  double r_, h_;
  int axis_;
};

}  // namespace nsf
