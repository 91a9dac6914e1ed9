#pragma once
// A solid bounded by a triangle mesh, usable wherever a shape is (CSG, transforms, weak regions).
#include "mpm/scene/geometry.h"
#include "mpm/scene/mesh/triangle_mesh.h"

namespace nsf {

// Repairs the mesh's orientation (orient_outward) and builds the query hierarchy. Inside means a
// generalised winding number ≥ ½; the signed distance's magnitude is the exact distance to the
// nearest triangle.
ShapePtr make_mesh_shape(TriangleMesh mesh);

}  // namespace nsf
