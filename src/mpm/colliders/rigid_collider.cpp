#include "mpm/colliders/rigid_collider.h"

namespace nsf {

void RigidCollider::apply(const Vec3& x, Vec3& v) const {
  Vec3 p = to_body(x);
  if (body_sdf(p) > 0.0) return;
  apply_contact(contact_, pose_.rotation * body_normal(p), pose_.velocity_at(x), v);
}

}  // namespace nsf
