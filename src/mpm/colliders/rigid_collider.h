#pragma once
// Common part of the rigid colliders: a shape described in its own body frame, a scripted pose,
// and a contact rule. A kind only supplies its body-frame signed distance and outward normal.
#include "mpm/colliders/collider.h"
#include "mpm/colliders/contact.h"
#include "mpm/colliders/rigid_motion.h"

namespace nsf {

class RigidCollider : public Collider {
 public:
  // The scripted pose at t, or, once a host drives the collider, the driven pose moved on to t.
  void set_time(double t) override;
  void apply(const Vec3& x, Vec3& v) const override;
  // From the distance at x alone, since body_sdf is 1-Lipschitz (a kind's contract, below).
  bool may_touch(const Vec3& x, double radius) const override;

  // Hands the collider to a host (a game engine moving it each frame): from now on its scripted
  // motion is ignored; at time t it is at `pose`, and it moves on rigidly with the pose's
  // velocity and angular velocity until the next call. The contact sees those velocities.
  void drive(const RigidPose& pose, double t);
  bool driven() const { return driven_; }

  // World-frame queries at the current pose (tests, rendering).
  double signed_distance(const Vec3& x) const { return body_sdf(to_body(x)); }
  Vec3 normal(const Vec3& x) const { return pose_.rotation * body_normal(to_body(x)); }
  Vec3 velocity_at(const Vec3& x) const { return pose_.velocity_at(x); }
  const RigidPose& pose() const { return pose_; }
  const ContactRule& contact() const { return contact_; }

 protected:
  RigidCollider(ContactRule contact, RigidMotion motion)
      : contact_(contact), motion_(std::move(motion)), pose_(motion_.at(0.0)) {}

  // Body frame: the collider's reference point at the origin, its rest orientation unrotated.
  // body_sdf must change by at most |a − b| between points a and b (an exact distance, or one
  // that underestimates), so that a block of grid nodes far from the surface can be skipped.
  virtual double body_sdf(const Vec3& p) const = 0;
  virtual Vec3 body_normal(const Vec3& p) const = 0;  // outward, unit length

 private:
  Vec3 to_body(const Vec3& x) const { return pose_.rotation.transpose() * (x - pose_.center); }

  ContactRule contact_;
  RigidMotion motion_;
  RigidPose pose_;
  bool driven_ = false;
  RigidPose driven_pose_;  // the host's pose at driven_time_
  double driven_time_ = 0;
};

}  // namespace nsf
