#pragma once
// Builds a shape tree from its scene JSON (docs/SCENES.md, "Shapes").
#include <nlohmann/json.hpp>
#include <string>

#include "mpm/scene/geometry.h"

namespace nsf {

// `path` names the node in errors, e.g. "objects[0].shape.children[1]".
ShapePtr parse_shape(const nlohmann::json& j, const std::string& path);

}  // namespace nsf
