#pragma once
// The rigid colliders of a scene as the renderer sees them: plain shapes at one pose. They are
// rebuilt from the scene JSON by the engine's own collider factory, so a picture shows exactly
// the box, cylinder or plane (and the scripted motion) the simulation used.
//
//   const SceneColliders colliders = SceneColliders::from_scene_json(run.scene_json());
//   opt.colliders = colliders.at(frame.time);
//   render_particles(frame.x, colors, opt);
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/types.h"

namespace nsf {

struct ColliderShape {
  enum class Kind { Box, Cylinder, Plane };
  Kind kind = Kind::Box;
  Vec3 center = Vec3::Zero();        // box/cylinder centre; a point on the plane
  Mat3 rotation = Mat3::Identity();  // body frame → world
  Vec3 half = Vec3::Zero();          // box: half the size along each body axis
  double radius = 0, height = 0;     // cylinder
  int axis = 1;                      // cylinder: its body axis (0, 1, 2)
  Vec3 normal = Vec3::UnitY();       // plane: unit, world frame, pointing out of the solid side
};

class SceneColliders {
 public:
  SceneColliders() = default;
  // `colliders`: the scene's "colliders" array (null: none). Builds each once now, so a collider
  // the engine would reject fails here, naming it, rather than in the middle of a render.
  explicit SceneColliders(nlohmann::json colliders);
  // From a scene JSON as stored in a run file (docs/OUTPUT.md, attribute `scene_json`).
  static SceneColliders from_scene_json(const std::string& scene_json);

  bool empty() const { return colliders_.empty(); }
  // Every collider at its scripted pose at time t. Builds fresh colliders on each call (cheap)
  // instead of moving shared ones, so frames may be drawn from several threads at once.
  std::vector<ColliderShape> at(double t) const;

 private:
  nlohmann::json colliders_ = nlohmann::json::array();
};

// World-space bounding box of a box or cylinder (a plane has none: false).
bool bounds(const ColliderShape& s, Vec3& lo, Vec3& hi);

}  // namespace nsf
