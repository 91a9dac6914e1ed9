// Grid update (§3.3 step 2): momentum → velocity, gravity, then colliders and domain walls.
// The stress force already arrived with the momentum in P2G.
#include <cmath>

#include "core/parallel_for.h"
#include "mpm/colliders/domain_walls.h"
#include "mpm/simulation.h"

namespace nsf {

void Simulation::grid_update(double dt) {
  ScopedTimer timer(times_.grid_update);
  const SimSettings& s = scene_.settings;
  const Vec3i n = grid_.dims();
  const Vec3 gdt = s.gravity * dt;
  GridNode* g = grid_.data();
  const auto& colliders = scene_.colliders;

  // Each block asks only the colliders that may reach its nodes (Collider::may_touch, one query
  // per block): the others would leave every node as it is, so the result is the same.
  constexpr size_t kMaxListed = 64;  // more colliders than this: every one asks every node
  const bool cull = !colliders.empty() && colliders.size() <= kMaxListed;

  parallel_for(long(active_blocks_.size()), [&](long q) {
    const Collider* reach[kMaxListed];
    size_t listed = 0;
    if (cull) {
      Vec3 lo, hi;
      block_node_bounds(active_blocks_[q], lo, hi);
      const Vec3 centre = 0.5 * (lo + hi);
      const double radius = 0.5 * (hi - lo).norm();
      for (const auto& c : colliders)
        if (c->may_touch(centre, radius)) reach[listed++] = c.get();
    }
    for_each_node_in_block(active_blocks_[q], [&](int i, int j, int k) {
      GridNode& node = g[grid_.index(i, j, k)];
      if (node.m <= 0) return;
      const double inv_m = 1.0 / node.m;
      Vec3 v(node.mv[0] * inv_m, node.mv[1] * inv_m, node.mv[2] * inv_m);
      v += gdt;
      if (cull) {
        if (listed) {
          const Vec3 x = grid_.node_position(i, j, k);
          for (size_t c = 0; c < listed; ++c) reach[c]->apply(x, v);
        }
      } else if (!colliders.empty()) {
        const Vec3 x = grid_.node_position(i, j, k);
        for (const auto& c : colliders) c->apply(x, v);
      }
      apply_domain_walls(s, i, j, k, n, v);
      node.mv[0] = v[0], node.mv[1] = v[1], node.mv[2] = v[2];
    });
  });
}

}  // namespace nsf
