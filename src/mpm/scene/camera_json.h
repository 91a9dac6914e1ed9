#pragma once
// The optional "camera" section of a scene: where `nsf render` looks from by default. The engine
// ignores it; it lives in the scene so that a scene's author, who knows what matters in it, picks
// the view once for every run of it.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "core/types.h"

namespace nsf {

struct SceneCamera {
  Vec3 eye = Vec3::Zero();
  Vec3 target = Vec3::Zero();
  Vec3 up = Vec3(0, 1, 0);
  double fov_deg = 40;  // vertical field of view (perspective)
};

// Reads scene["camera"] when present; fails naming the key for a malformed one.
std::optional<SceneCamera> parse_camera(const nlohmann::json& scene);

}  // namespace nsf
