#include "mpm/colliders/collider_limits.h"

#include <sstream>

#include "mpm/scene/scene.h"

namespace nsf {

namespace {

std::string text(const Vec3& v) {
  std::ostringstream os;
  os << "[" << v[0] << ", " << v[1] << ", " << v[2] << "]";
  return os.str();
}

}  // namespace

ColliderLimits collider_limits(const SimSettings& s) {
  ColliderLimits l;
  const Vec3 size = s.domain_hi - s.domain_lo;
  l.lo = s.domain_lo - size;
  l.hi = s.domain_hi + size;
  l.speed = s.cfl * s.dx / s.dt;
  l.angular_speed = l.speed / size.norm();
  return l;
}

std::string collider_motion_problem(const ColliderLimits& l, size_t i, const Vec3& position,
                                    const Vec3& velocity, const Vec3& angular_velocity) {
  std::ostringstream os;
  if (!(position.array() >= l.lo.array()).all() || !(position.array() <= l.hi.array()).all())
    os << "collider " << i << "'s position " << text(position)
       << " is outside the scene's domain grown by its size on every side (" << text(l.lo) << " to "
       << text(l.hi) << ")";
  else if (!(velocity.norm() <= l.speed))
    os << "collider " << i << "'s velocity " << text(velocity) << " m/s is over the limit of "
       << l.speed << " m/s (the scene's CFL speed cfl*dx/dt: no particle may move faster)";
  else if (!(angular_velocity.norm() <= l.angular_speed))
    os << "collider " << i << "'s angular velocity " << text(angular_velocity)
       << " rad/s is over the limit of " << l.angular_speed
       << " rad/s (the scene's CFL speed at one domain diagonal from its reference point)";
  return os.str();
}

}  // namespace nsf
