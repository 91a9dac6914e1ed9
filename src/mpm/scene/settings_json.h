#pragma once
// Reads the "simulation" section of a scene into SimSettings.
#include <nlohmann/json.hpp>
#include <string>

#include "mpm/scene/scene.h"

namespace nsf {

SimSettings parse_settings(const nlohmann::json& j, const std::string& path = "simulation");

}  // namespace nsf
