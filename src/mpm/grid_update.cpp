// Grid update (§3.3 step 2): momentum → velocity, gravity, then colliders and domain walls.
// The stress force already arrived with the momentum in P2G.
#include <cmath>

#include "mpm/simulation.h"

namespace nsf {

namespace {

// Contact with the domain walls: the outer `wall_nodes` layers of each face.
void apply_walls(const SimSettings& s, const Vec3i& n, int idx[3], Vec3& v) {
  for (int d = 0; d < 3; ++d) {
    double normal = 0;  // inward normal component along axis d
    if (idx[d] < s.wall_nodes) normal = 1;
    else if (idx[d] >= n[d] - s.wall_nodes) normal = -1;
    if (normal == 0) continue;
    if (s.wall_contact == Contact::Sticky) {
      v.setZero();
      return;
    }
    double vn = v[d] * normal;
    if (vn >= 0) continue;  // moving away from the wall
    v[d] = 0;
    if (s.wall_contact == Contact::Friction) {
      Vec3 vt = v;
      double vt_norm = vt.norm();
      // Coulomb: tangential speed drops by μ|v_n|, and stops if that exceeds it.
      if (vt_norm <= -s.wall_friction * vn) v.setZero();
      else v = vt * (1.0 + s.wall_friction * vn / vt_norm);
    }
  }
}

}  // namespace

void Simulation::grid_update() {
  ScopedTimer timer(times_.grid_update);
  const SimSettings& s = scene_.settings;
  const Vec3i n = grid_.dims();
  const double dt = s.dt;
  const Vec3 gdt = s.gravity * dt;
  GridNode* g = grid_.data();
  const auto& colliders = scene_.colliders;

#pragma omp parallel for schedule(static)
  for (long q = 0; q < long(active_blocks_.size()); ++q)
    for_each_node_in_block(active_blocks_[q], [&](int i, int j, int k) {
      GridNode& node = g[grid_.index(i, j, k)];
      if (node.m <= 0) return;
      const double inv_m = 1.0 / node.m;
      Vec3 v(node.mv[0] * inv_m, node.mv[1] * inv_m, node.mv[2] * inv_m);
      v += gdt;
      if (!colliders.empty()) {
        const Vec3 x = grid_.node_position(i, j, k);
        for (const auto& c : colliders) c->apply(x, v);
      }
      int idx[3] = {i, j, k};
      apply_walls(s, n, idx, v);
      node.mv[0] = v[0], node.mv[1] = v[1], node.mv[2] = v[2];
    });
}

}  // namespace nsf
