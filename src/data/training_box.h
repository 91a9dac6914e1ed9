#pragma once
// The box a model was trained on (issue #55 item 4): the range of each swept parameter (μ and the
// sweep's "vary" axes) over the training runs, and for each collider the region its centre moved
// in and the fastest it moved. `nsf sweep` stores each run's part in the run file, `nsf train`
// their union in the model, and the reduced-order runtime says when a run leaves it
// (rom/step/step_guard.h), since a latent space holds only the motions its training runs made.
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/types.h"
#include "data/scene_family.h"
#include "mpm/colliders/collider.h"

namespace nsf {

struct ParameterRange {
  std::string name;
  double lo = 0, hi = 0;
};

struct ColliderEnvelope {
  int collider = 0;                           // index in the scene's "colliders"
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  // the box its centre stayed in, m
  double max_speed = 0;                       // of its centre, m/s
  double max_angular_speed = 0;               // rad/s
};

struct TrainingBox {
  std::vector<ParameterRange> parameters;
  std::vector<ColliderEnvelope> colliders;
  // Every value of the training runs' scenes (empty in files written before nsf recorded it).
  SceneFamily scene;

  bool empty() const { return parameters.empty() && colliders.empty() && scene.empty(); }
  // Grows this box to hold `other` too (parameters and colliders matched by name and index).
  void include(const TrainingBox& other);

  // One line per parameter and collider, for people: "hardening in [0, 0.2]", "collider 1's
  // centre in [0.25, 0.34] x [0.29, 0.3] x [0.49, 0.51] m, at most 0.98 m/s".
  std::vector<std::string> describe() const;

  nlohmann::json to_json() const;
  // Throws nsf::Error naming `where` and the key when `j` is not a box as to_json writes it.
  static TrainingBox from_json(const nlohmann::json& j, const std::string& where);

  // "" when collider i at `center`, moving at `speed` (m/s), lies within the box grown by
  // `tolerance` metres and 10 % of the fastest speed; else what lies outside, e.g. "collider 1's
  // centre is 0.042 m beyond its training box in x (its runs stayed in [0.30, 0.35])". A collider
  // the box does not hold is never outside.
  std::string collider_outside(size_t i, const Vec3& center, double speed, double tolerance) const;
};

// Records the colliders' centres and speeds over a run (RigidCollider poses; other colliders are
// left out), one call per saved frame.
class ColliderEnvelopeRecorder {
 public:
  void record(const std::vector<std::unique_ptr<Collider>>& colliders);
  const TrainingBox& box() const { return box_; }

 private:
  TrainingBox box_;
};

}  // namespace nsf
