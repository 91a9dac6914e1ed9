#pragma once
// Builds a shape tree from its scene JSON (docs/SCENES.md, "Shapes").
#include <nlohmann/json.hpp>
#include <string>

#include "mpm/scene/geometry.h"

namespace nsf {

// What a shape may need besides its JSON: mesh files name paths relative to the scene file.
struct ShapeContext {
  std::string base_dir;  // relative file paths resolve against it; empty: the working directory
};

// `path` names the node in errors, e.g. "objects[0].shape.children[1]".
ShapePtr parse_shape(const nlohmann::json& j, const std::string& path,
                     const ShapeContext& context = {});

}  // namespace nsf
