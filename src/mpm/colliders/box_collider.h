#pragma once
// A solid rigid box (e.g. a spatula blade, a grip), optionally rotated and scripted to move.
#include <nlohmann/json.hpp>
#include <string>

#include "core/sdf.h"
#include "mpm/colliders/rigid_collider.h"

namespace nsf {

class BoxCollider : public RigidCollider {
 public:
  BoxCollider(const Vec3& size, ContactRule contact, RigidMotion motion)
      : RigidCollider(contact, std::move(motion)), half_(0.5 * size) {}
  static std::unique_ptr<Collider> parse(const nlohmann::json& j, const std::string& path);
  std::string type() const override { return "box"; }
  const Vec3& half_size() const { return half_; }  // body frame, for drawing

 protected:
  double body_sdf(const Vec3& p) const override { return sdf::box(p, half_); }
  Vec3 body_normal(const Vec3& p) const override { return sdf::box_normal(p, half_); }

 private:
  Vec3 half_;
};

}  // namespace nsf
