#pragma once
// Random smooth collider paths for a sweep's training runs (issue #55 item 4; docs/SCENES.md,
// "Sweeps"): a user who will move a tool by hand trains on runs in which the tool wanders, so that
// the latent space holds motions no single scripted run makes.
//   {"name": "left plate wanders", "collider": 1, "start": 0.05, "end": 0.6,
//    "offset": [0.02, 0.01, 0.02], "max_speed": 0.6}
// Each run's path is the collider's scripted motion plus a smooth offset o(s), s = (t − start) /
// (end − start): o(s) = a · Σₖ₌₁³ cₖ sin(kπs) / k with cₖ uniform in [−1, 1]³ per axis, scaled
// so that its largest excursion along some axis is a·offset there, with a uniform in [0.5, 1].
// The offset is zero at start and end, so the path leaves and rejoins the script smoothly. It is
// shrunk until no keyframe segment moves the collider faster than max_speed. The path is written
// as keyframes at every frame time (the collider's "motion"), orientations from the script.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "core/types.h"

namespace nsf {

struct ColliderPath {
  std::string name;
  int collider = 0;            // index in the scene's "colliders"
  double start = 0, end = 0;   // seconds, start < end ≤ the scene's end
  Vec3 offset = Vec3::Zero();  // largest excursion per axis, m (≥ 0, not all zero)
  double max_speed = 0;        // m/s of the collider's centre
};

// Reads and checks a path at `path` (e.g. "sweep.paths[0]") against `scene`: the collider must
// exist and be rigid, and a path must be drawable (the script alone no faster than max_speed).
ColliderPath parse_collider_path(const nlohmann::json& j, const std::string& path,
                                 const nlohmann::json& scene);

// The override "colliders[i].motion={"keyframes": [...]}" of the path drawn from `seed` over
// `scene` (the collider's script as the scene has it now). Throws nsf::Error when the script is
// faster than max_speed.
std::string collider_path_override(const ColliderPath& path, const nlohmann::json& scene,
                                   uint64_t seed);

}  // namespace nsf
