#pragma once
// How far and how fast a host may drive a collider (nsf serve's move command, the embedding API's
// Runtime::set_collider_pose, Python's Rom.set_collider_pose). Without bounds a finite but absurd
// value was taken: a move to 1.8e308 m streamed infinite poses, an angular velocity of 1e308 rad/s
// turned the rotation to NaN.
#include <cstddef>
#include <string>

#include "core/types.h"

namespace nsf {

struct SimSettings;

struct ColliderLimits {
  // The reference point stays in the domain grown by its own size on every side (for a domain
  // [0, 1]³: [-1, 2]³), so a collider may start, or be put, partly outside it.
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
  // m/s: the scene's CFL speed cfl·dx/dt, the fastest the engine lets a particle move; a collider
  // faster than that could only throw the material out of the grid.
  double speed = 0;
  // rad/s: that speed at one domain diagonal from the reference point.
  double angular_speed = 0;
};

ColliderLimits collider_limits(const SimSettings& settings);

// "" when collider i's position and velocities lie within the limits, else what does not, with
// the value and the limit ("collider 0's velocity [0, 1000, 0] m/s is over the limit of 24 m/s
// (...)"). Non-finite values are out of every limit.
std::string collider_motion_problem(const ColliderLimits& limits, size_t i, const Vec3& position,
                                    const Vec3& velocity, const Vec3& angular_velocity);

}  // namespace nsf
