#pragma once
// Makes a triangle mesh's orientation consistent, with normals pointing out of the solid.
#include "mpm/scene/mesh/triangle_mesh.h"

namespace nsf {

// Flips triangles so that neighbours (sharing an edge used by exactly two triangles) traverse
// their shared edge in opposite directions, then flips each edge-connected component whose
// enclosed signed volume is negative. Exported meshes often have a few triangles (or whole
// parts) wound the wrong way; the winding number needs them consistent. Returns the number of
// triangles flipped.
size_t orient_outward(TriangleMesh& mesh);

}  // namespace nsf
