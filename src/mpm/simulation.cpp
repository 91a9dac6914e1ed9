#include "mpm/simulation.h"
#include "core/parallel_for.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "mpm/bspline.h"

namespace nsf {

namespace {
constexpr int kBlock = 4;  // cells per grid block edge; a stencil spans at most 2 blocks
}

Simulation::Simulation(Scene scene) : scene_(std::move(scene)) {
  const SimSettings& s = scene_.settings;
  grid_ = Grid(s.domain_lo, s.domain_hi, s.dx);
  if (scene_.particles.size() == 0) fail("simulation: the scene has no particles");
  if (scene_.materials.empty()) fail("simulation: the scene has no materials");
  for (size_t p = 0; p < scene_.particles.size(); ++p)
    if (scene_.particles.material[p] >= scene_.materials.size())
      fail("simulation: particle ", p, " refers to material ", scene_.particles.material[p],
           " but the scene has ", scene_.materials.size());
  check_time_step();
  check_particles();
  // τ^0 from the initial F so the first P2G sees the initial stress state.
  update_stress();
  for (auto& c : scene_.colliders) c->set_time(0.0);
}

double cfl_time_step_bound(const Scene& scene, double* wave_speed, size_t* particle) {
  // Explicit MPM is stable only if an elastic wave crosses less than a cell per step.
  const Particles& P = scene.particles;
  double worst = 0;
  size_t worst_p = 0;
  for (size_t p = 0; p < P.size(); ++p) {
    double rho = P.mass[p] / P.vol0[p];
    double c = std::sqrt(Material::p_wave_modulus(P.mat[p]) / rho);
    if (c > worst) worst = c, worst_p = p;
  }
  if (wave_speed) *wave_speed = worst;
  if (particle) *particle = worst_p;
  return scene.settings.cfl * scene.settings.dx / std::max(worst, 1e-30);
}

void Simulation::check_time_step() const {
  double worst = 0;
  size_t worst_p = 0;
  const double bound = cfl_time_step_bound(scene_, &worst, &worst_p);
  const SimSettings& s = scene_.settings;
  if (s.dt > bound)
    fail("simulation: dt = ", s.dt, " exceeds the CFL bound ", bound, " (elastic wave speed ",
         worst, " m/s at particle ", worst_p, ", dx = ", s.dx, ", cfl = ", s.cfl,
         "). Lower simulation.dt to at most ", bound, " or soften the material.");
}

void Simulation::step() {
  // §3.3: P2G (with the stress force fused in), grid update, G2P, return map.
  transfer(scene_.settings.dt, time_);
  update_stress();
  time_ += scene_.settings.dt;
  ++steps_;
  check_particles();
}

void Simulation::transfer(double dt, double t, const std::vector<uint32_t>* gather) {
  for (auto& c : scene_.colliders) c->set_time(t);
  sort_particles();
  p2g(dt);
  grid_update(dt);
  g2p(dt, gather);
}

void Simulation::advance_frame() {
  for (int i = 0; i < scene_.settings.substeps; ++i) step();
}

void Simulation::sort_particles() {
  ScopedTimer timer(times_.sort);
  const Particles& P = scene_.particles;
  const Vec3i n = grid_.dims();
  int nb[3];
  for (int d = 0; d < 3; ++d) nb[d] = (n[d] + kBlock - 1) / kBlock;
  block_dims_.assign(nb, nb + 3);
  const size_t blocks = size_t(nb[0]) * nb[1] * nb[2];
  const size_t np = P.size();

  // Stable counting sort by block keeps each block's particle order fixed, so the scatter
  // order, and with it every floating-point sum, is the same for any thread count.
  std::vector<uint32_t>& key = sort_key_;
  std::vector<uint32_t>& count = block_start_;
  key.resize(np);
  count.assign(blocks + 1, 0);
  parallel_for(long(np), [&](long p) {
    Stencil st = quadratic_stencil(P.x[p], grid_.lo(), grid_.inv_dx());
    size_t b =
        (size_t(st.base[0] / kBlock) * nb[1] + st.base[1] / kBlock) * nb[2] + st.base[2] / kBlock;
    key[p] = static_cast<uint32_t>(b);
  });
  for (size_t p = 0; p < np; ++p) ++count[key[p] + 1];
  for (size_t b = 0; b < blocks; ++b) count[b + 1] += count[b];
  order_.resize(np);
  // Filled through the block starts, which it moves on by one block each; shifted back after.
  for (size_t p = 0; p < np; ++p) order_[count[key[p]]++] = static_cast<uint32_t>(p);
  for (size_t b = blocks; b > 0; --b) count[b] = count[b - 1];
  count[0] = 0;

  color_blocks_.resize(8);
  for (auto& list : color_blocks_) list.clear();
  // 1: a block some stencil reaches now; 2: one last step reached (to clear, not to update).
  std::vector<uint8_t>& active = block_flags_;
  active.assign(blocks, 0);
  for (int bi = 0; bi < nb[0]; ++bi)
    for (int bj = 0; bj < nb[1]; ++bj)
      for (int bk = 0; bk < nb[2]; ++bk) {
        size_t b = (size_t(bi) * nb[1] + bj) * nb[2] + bk;
        if (block_start_[b + 1] == block_start_[b]) continue;
        int color = (bi & 1) | ((bj & 1) << 1) | ((bk & 1) << 2);
        color_blocks_[color].push_back(static_cast<uint32_t>(b));
        for (int di = 0; di < 2 && bi + di < nb[0]; ++di)
          for (int dj = 0; dj < 2 && bj + dj < nb[1]; ++dj)
            for (int dk = 0; dk < 2 && bk + dk < nb[2]; ++dk)
              active[(size_t(bi + di) * nb[1] + bj + dj) * nb[2] + bk + dk] = 1;
      }
  for (uint32_t b : active_blocks_)
    if (b < blocks) active[b] |= 2;
  active_blocks_.clear();
  blocks_to_clear_.clear();
  for (size_t b = 0; b < blocks; ++b) {
    if (active[b] & 1) active_blocks_.push_back(static_cast<uint32_t>(b));
    if (active[b]) blocks_to_clear_.push_back(static_cast<uint32_t>(b));
  }
}

void Simulation::block_node_bounds(uint32_t b, Vec3& lo, Vec3& hi) const {
  const int nb1 = block_dims_[1], nb2 = block_dims_[2];
  const int bk = b % nb2, bj = (b / nb2) % nb1, bi = b / (nb2 * nb1);
  const Vec3i n = grid_.dims();
  lo = grid_.node_position(bi * kBlock, bj * kBlock, bk * kBlock);
  hi = grid_.node_position(std::min(n[0], (bi + 1) * kBlock) - 1,
                           std::min(n[1], (bj + 1) * kBlock) - 1,
                           std::min(n[2], (bk + 1) * kBlock) - 1);
}

void Simulation::clear_active_grid() {
  // This step's blocks and last step's, each once, so no stale node values survive anywhere on
  // the grid. Called inside P2G's parallel region: the loop is shared out over its team
  // (orphaned `omp for`), and the barrier after it keeps the scatter from starting early.
  GridNode* g = grid_.data();
#pragma omp for schedule(static)
  for (long q = 0; q < long(blocks_to_clear_.size()); ++q)
    for_each_node_in_block(blocks_to_clear_[q], [&](int i, int j, int k) {
      g[grid_.index(i, j, k)] = GridNode{{0, 0, 0}, 0};
    });
}

}  // namespace nsf
