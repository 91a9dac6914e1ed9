#pragma once
// Turns one entry of the scene's "objects" array into particles: samples its shape, builds the
// per-particle material record (scaled inside weak regions) and the initial velocity.
#include <nlohmann/json.hpp>
#include <string>

#include "mpm/scene/scene.h"
#include "mpm/scene/shape_json.h"

namespace nsf {

// Appends the particles of object `index` (at `path`, e.g. "objects[2]") to scene.particles,
// adding its material model to scene.materials if no earlier object used the same type.
void add_object(const nlohmann::json& obj, const std::string& path, size_t index,
                const ShapeContext& context, Scene& scene);

}  // namespace nsf
