#pragma once
// The full-order explicit MPM engine (§3.3 of the paper): P2G, grid update, G2P, return map.
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

class Simulation {
 public:
  explicit Simulation(Scene scene);

  void step();          // advance by one time step dt
  void advance_frame(); // advance by settings.substeps steps

  double time() const { return time_; }
  long step_count() const { return steps_; }
  const Scene& scene() const { return scene_; }
  const SimSettings& settings() const { return scene_.settings; }
  Particles& particles() { return scene_.particles; }
  const Particles& particles() const { return scene_.particles; }
  const Grid& grid() const { return grid_; }
  const StepTimes& times() const { return times_; }

  // Throws nsf::Error if Δt exceeds the CFL bound for the stiffest material (checked at start).
  void check_time_step() const;

 private:
  void sort_particles();  // bucket particles by grid block for the race-free coloured scatter
  void p2g();
  void grid_update();
  void g2p();
  void update_stress();
  void check_particles() const;  // guards: NaN, leaving the domain, CFL on particle speed

  Scene scene_;
  Grid grid_;
  double time_ = 0;
  long steps_ = 0;
  StepTimes times_;

  // Particles bucketed by 4x4x4-cell grid block; blocks of one colour never share a node.
  std::vector<int> block_dims_;              // blocks per axis
  std::vector<uint32_t> order_;              // particle indices sorted by block
  std::vector<uint32_t> block_start_;        // offsets into order_, one more than blocks
  std::vector<std::vector<uint32_t>> color_blocks_;  // non-empty blocks of each of 8 colours
};

}  // namespace nsf
