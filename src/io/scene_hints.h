#pragma once
// What a picture of a run can learn from the scene JSON stored in it: particle size, where the
// floor is, a camera, and names for the legend. Every lookup is forgiving (a hand-written or older
// run may lack any of it) except the camera, which the user wrote on purpose and should hear about.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/types.h"
#include "mpm/scene/camera_json.h"

namespace nsf {

struct SceneHints {
  double particle_radius = 0;  // half the particle spacing, dx / (2 ppc); 0 when unknown
  // Height of the floor the material rests on: an upward-facing plane collider, else the top of
  // the domain's bottom wall; unset when the scene says neither.
  std::optional<double> floor_height;
  std::optional<SceneCamera> camera;
  std::vector<std::string> object_names;    // "object 0 (von Mises)", by object index
  std::vector<std::string> material_names;  // "Drucker–Prager", by material index
};

// A material model's name for people: "von_mises" -> "von Mises".
std::string material_display_name(const std::string& type);

// `scene_json` as stored in a run's `scene_json` attribute; `dx` is the run's grid spacing.
// Fails only for a malformed "camera" section.
SceneHints scene_hints(const std::string& scene_json, double dx);

}  // namespace nsf
