#pragma once
// An indexed triangle mesh as read from a mesh file, before it becomes a solid shape.
#include <array>
#include <vector>

#include "core/types.h"

namespace nsf {

struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;  // indices into vertices
};

// Merges vertices at bit-identical positions and drops triangles that become degenerate.
// STL stores a triangle soup and OBJ may repeat positions per face; the orientation repair needs
// neighbouring triangles to share vertex indices.
void weld_vertices(TriangleMesh& mesh);

}  // namespace nsf
