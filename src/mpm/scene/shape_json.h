#pragma once
// Builds a shape tree from its scene JSON (docs/SCENES.md, "Shapes").
#include <nlohmann/json.hpp>
#include <string>

#include "mpm/scene/geometry.h"

namespace nsf {

// What a shape may need besides its JSON: mesh files name paths relative to the scene file.
struct ShapeContext {
  std::string base_dir;  // relative file paths resolve against it; empty: the working directory
  int depth = 0;         // CSG nodes above this one; parse_shape refuses more than kMaxShapeDepth
};

// The deepest CSG nesting a scene may have. Parsing recurses once per level, so without a bound a
// hostile scene nested thousands deep overflows the stack; real scenes nest a handful of levels.
constexpr int kMaxShapeDepth = 64;

// `path` names the node in errors, e.g. "objects[0].shape.children[1]".
ShapePtr parse_shape(const nlohmann::json& j, const std::string& path,
                     const ShapeContext& context = {});

}  // namespace nsf
