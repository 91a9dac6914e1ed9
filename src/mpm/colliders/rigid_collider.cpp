#include "mpm/colliders/rigid_collider.h"

#include <Eigen/Geometry>

namespace nsf {

void RigidCollider::set_time(double t) {
  if (!driven_) {
    pose_ = motion_.at(t);
    return;
  }
  // Rigid motion at constant velocities from the host's pose: c + v·τ, exp(τ·[ω]) R.
  const double tau = t - driven_time_;
  pose_ = driven_pose_;
  pose_.center += tau * driven_pose_.velocity;
  const double angle = tau * driven_pose_.angular_velocity.norm();
  if (angle != 0.0)
    pose_.rotation =
        Eigen::AngleAxisd(angle, driven_pose_.angular_velocity.normalized()).toRotationMatrix() *
        driven_pose_.rotation;
}

void RigidCollider::drive(const RigidPose& pose, double t) {
  driven_ = true;
  driven_pose_ = pose;
  driven_time_ = t;
  set_time(t);
}

void RigidCollider::apply(const Vec3& x, Vec3& v) const {
  Vec3 p = to_body(x);
  if (body_sdf(p) > 0.0) return;
  apply_contact(contact_, pose_.rotation * body_normal(p), pose_.velocity_at(x), v);
}

bool RigidCollider::may_touch(const Vec3& x, double radius) const {
  // A node within `radius` of x has a distance of at least sdf(x) − radius; the margin, far
  // above rounding, keeps a node the exact test would touch from ever being skipped.
  return body_sdf(to_body(x)) <= radius * (1 + 1e-6) + 1e-12;
}

}  // namespace nsf
