#pragma once
// A half-space: everything on the side opposite to "normal" from "point" is solid. Any
// orientation is allowed (inclined planes); the normal need not be unit length in the scene.
#include <nlohmann/json.hpp>
#include <string>

#include "mpm/colliders/rigid_collider.h"

namespace nsf {

class PlaneCollider : public RigidCollider {
 public:
  PlaneCollider(const Vec3& normal, ContactRule contact, RigidMotion motion)
      : RigidCollider(contact, std::move(motion)), n_(normal.normalized()) {}
  static std::unique_ptr<Collider> parse(const nlohmann::json& j, const std::string& path);
  std::string type() const override { return "plane"; }

 protected:
  double body_sdf(const Vec3& p) const override { return p.dot(n_); }
  Vec3 body_normal(const Vec3&) const override { return n_; }

 private:
  Vec3 n_;
};

}  // namespace nsf
