#pragma once
// Reads a triangle mesh file (OBJ, ASCII or binary STL, and the other formats Assimp knows).
#include <string>

#include "mpm/scene/mesh/triangle_mesh.h"

namespace nsf {

// Throws nsf::Error naming `file` and the scene key `key_path` if the file is missing, cannot be
// parsed, or holds no triangle. The result is welded (see weld_vertices).
TriangleMesh read_triangle_mesh(const std::string& file, const std::string& key_path);

}  // namespace nsf
