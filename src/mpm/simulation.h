#pragma once
// The full-order explicit MPM engine (§3.3 of the paper): P2G, grid update, G2P, return map.
#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "core/timer.h"
#include "mpm/grid.h"
#include "mpm/scene/scene.h"

namespace nsf {

// Wall time spent in each phase of the step, for the benchmark breakdown.
struct StepTimes {
  PhaseTimer sort, p2g, grid_update, g2p, stress;
};

// The largest stable explicit Δt: cfl · Δx / (fastest elastic wave speed over the particles).
// Optionally returns that speed and the particle it belongs to.
double cfl_time_step_bound(const Scene& scene, double* wave_speed = nullptr,
                           size_t* particle = nullptr);

class Simulation {
 public:
  explicit Simulation(Scene scene);

  void step();           // advance by one time step dt
  void advance_frame();  // advance by settings.substeps steps

  // The transfers of one step over whatever particles() holds, without the return map: colliders
  // at time t, P2G of every particle with its current τ, grid update, then G2P (x, v, C and the
  // trial F) for the `gather` particles only, or for all when `gather` is null. The reduced-order
  // model (§5.2) runs this on its integration particles N with inferred states and G2P on the
  // sample particles S; time() and step_count() do not change and no guard runs.
  void transfer(double dt, double t, const std::vector<uint32_t>* gather = nullptr);

  double time() const { return time_; }
  long step_count() const { return steps_; }
  const Scene& scene() const { return scene_; }
  // Hands the scene back, its particles as the last step left them and its colliders at the last
  // step's time; the simulation is left without one.
  Scene release_scene() && { return std::move(scene_); }
  const SimSettings& settings() const { return scene_.settings; }
  Particles& particles() { return scene_.particles; }
  const Particles& particles() const { return scene_.particles; }
  // The scene's colliders, for a host that moves them between steps (RigidCollider::drive).
  std::vector<std::unique_ptr<Collider>>& colliders() { return scene_.colliders; }
  const Grid& grid() const { return grid_; }
  const StepTimes& times() const { return times_; }

  // Throws nsf::Error if Δt exceeds cfl_time_step_bound (checked at start).
  void check_time_step() const;

 private:
  void sort_particles();  // bucket particles by grid block for the race-free coloured scatter
  void p2g(double dt);
  void grid_update(double dt);
  void g2p(double dt, const std::vector<uint32_t>* gather);
  void update_stress();
  void check_particles() const;  // guards: NaN, leaving the domain, CFL on particle speed

  Scene scene_;
  Grid grid_;
  double time_ = 0;
  long steps_ = 0;
  StepTimes times_;

  // Particles bucketed by 4x4x4-cell grid block; blocks of one colour never share a node.
  std::vector<int> block_dims_;                      // blocks per axis
  std::vector<uint32_t> order_;                      // particle indices sorted by block
  std::vector<uint32_t> block_start_;                // offsets into order_, one more than blocks
  std::vector<std::vector<uint32_t>> color_blocks_;  // non-empty blocks of each of 8 colours
  // Blocks whose nodes some particle's stencil reaches (non-empty blocks and their +1
  // neighbours); only these are cleared and updated, so empty space costs nothing.
  std::vector<uint32_t> active_blocks_;
  std::vector<uint32_t> blocks_to_clear_;  // this step's active blocks and last step's
  // Scratch of sort_particles, kept between steps: each particle's block, each block's flags.
  std::vector<uint32_t> sort_key_;
  std::vector<uint8_t> block_flags_;

  // Calls f(i, j, k) for every grid node of block b.
  template <typename Fn>
  void for_each_node_in_block(uint32_t b, Fn&& f) const;
  // The positions of block b's first and last grid nodes (its nodes' bounding box).
  void block_node_bounds(uint32_t b, Vec3& lo, Vec3& hi) const;
  void clear_active_grid();  // call from inside a parallel region
};

template <typename Fn>
void Simulation::for_each_node_in_block(uint32_t b, Fn&& f) const {
  constexpr int kBlockCells = 4;
  const int nb1 = block_dims_[1], nb2 = block_dims_[2];
  const int bk = b % nb2, bj = (b / nb2) % nb1, bi = b / (nb2 * nb1);
  const Vec3i n = grid_.dims();
  const int i1 = std::min(n[0], (bi + 1) * kBlockCells),
            j1 = std::min(n[1], (bj + 1) * kBlockCells),
            k1 = std::min(n[2], (bk + 1) * kBlockCells);
  for (int i = bi * kBlockCells; i < i1; ++i)
    for (int j = bj * kBlockCells; j < j1; ++j)
      for (int k = bk * kBlockCells; k < k1; ++k) f(i, j, k);
}

}  // namespace nsf
