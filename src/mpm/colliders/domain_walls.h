#pragma once
// The domain boundary: the outer `wall_nodes` layers of grid nodes on each face act as a wall
// with the scene's wall contact rule ("simulation.walls"). The engine calls this for every node
// after the grid update; only nodes in a wall layer are changed.
#include "core/types.h"
#include "mpm/scene/scene.h"

namespace nsf {

// (i, j, k): node index; dims: nodes per axis of the grid.
void apply_domain_walls(const SimSettings& settings, int i, int j, int k, const Vec3i& dims,
                        Vec3& v);

}  // namespace nsf
