#pragma once
// Rigid colliders act on grid node velocities after the grid update (§3.3 step 2): a node inside
// (or on) the collider has its velocity, relative to the collider's own velocity there, made
// sticky (zero), slip (normal component removed if approaching) or slip with Coulomb friction.
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "core/types.h"

namespace nsf {

enum class Contact { Sticky, Slip, Friction };

class Collider {
 public:
  virtual ~Collider() = default;
  virtual std::string type() const = 0;

  // Moves the collider to its scripted pose at time t (called once per step, before the grid
  // update).
  virtual void set_time(double t) = 0;

  // Applies the contact condition to the velocity v of a grid node at position x, if the node is
  // in contact. Must be thread-safe (called concurrently for different nodes).
  virtual void apply(const Vec3& x, Vec3& v) const = 0;

  // False only if apply() leaves the velocity of every node within `radius` of x unchanged (no
  // such node is in contact): the grid update then skips this collider for a whole block of
  // nodes. Conservative; the default, true, makes every node ask apply().
  virtual bool may_touch(const Vec3& x, double radius) const {
    (void)x, (void)radius;
    return true;
  }
};

// Builds a collider from its scene JSON (`path` is used in error messages, e.g. "colliders[0]").
std::unique_ptr<Collider> make_collider(const nlohmann::json& j, const std::string& path);

}  // namespace nsf
