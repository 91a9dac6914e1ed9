#pragma once
// Scripted rigid motion of a collider (docs/SCENES.md, "Collider motion"). Either constant
// velocities over a time window, or keyframed poses interpolated linearly (centre) and by slerp
// (orientation). Outside the scripted times the collider rests at its first/last pose.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/types.h"

namespace nsf {

struct RigidPose {
  Vec3 center = Vec3::Zero();
  Mat3 rotation = Mat3::Identity();      // body frame → world
  Vec3 velocity = Vec3::Zero();          // of the centre
  Vec3 angular_velocity = Vec3::Zero();  // rad/s, world frame, about the centre

  // Velocity of the body point currently at x: v + ω × (x − c).
  Vec3 velocity_at(const Vec3& x) const { return velocity + angular_velocity.cross(x - center); }
};

class RigidMotion {
 public:
  // A collider that never moves.
  RigidMotion(const Vec3& center, const Mat3& rotation);

  // Reads the optional "motion" key of `collider` (at `path`); `center`/`rotation` are the rest
  // pose given by the collider's own keys.
  static RigidMotion parse(const nlohmann::json& collider, const std::string& path,
                           const Vec3& center, const Mat3& rotation);

  RigidPose at(double t) const;

 private:
  struct Keyframe {
    double t;
    Vec3 center;
    Eigen::Quaterniond rotation;
  };
  RigidPose at_velocity(double t) const;
  RigidPose at_keyframes(double t) const;

  Vec3 center0_;
  Mat3 rotation0_;
  // Constant-velocity script (active for start_ <= t < end_).
  Vec3 velocity_ = Vec3::Zero();
  Vec3 angular_velocity_ = Vec3::Zero();
  double start_ = 0.0;
  double end_ = 0.0;
  std::vector<Keyframe> keys_;  // non-empty: keyframed script
};

}  // namespace nsf
