// P2G (§3.3 step 1), with the stress force of step 2 fused in (MLS-MPM, Hu et al. 2018):
// with ∇w_ip = w_ip · D⁻¹ (x_i − x_p), D⁻¹ = 4/Δx², the force −V⁰ τ ∇w_ip is an affine term,
// so momentum and force reach node i in one scatter:
//   m_i v_i += w_ip [ m_p v_p + (m_p C_p − Δt V⁰ D⁻¹ τ_p)(x_i − x_p) ].
#include <omp.h>

#include "core/isa.h"
#include "mpm/bspline.h"
#include "mpm/simulation.h"

namespace nsf {

namespace {

static_assert(sizeof(GridNode) == 4 * sizeof(double), "a node must be one 4-wide vector");

// Adds w_ip [m_p v_p + A (x_i − x_p), w_ip m_p] to the 27 nodes of the stencil. A GridNode is four
// doubles (momentum, mass), so each node update is one 4-wide fused multiply-add on one 32-byte
// load/store: momentum and mass go as one vector, with A's columns padded by a zero mass lane.
inline void scatter_particle(const Stencil& st, double dx, const Vec3& mv, double m, const Mat3& A,
                             GridNode* g, size_t si, size_t sj) {
  const simd4 base = {mv[0], mv[1], mv[2], m};
  const simd4 a0 = {A(0, 0), A(1, 0), A(2, 0), 0.0}, a1 = {A(0, 1), A(1, 1), A(2, 1), 0.0},
              a2 = {A(0, 2), A(1, 2), A(2, 2), 0.0};
  // Offsets x_i − x_p along each axis, in world units, for stencil offsets 0, 1, 2.
  double d[3][3];
  for (int ax = 0; ax < 3; ++ax)
    for (int o = 0; o < 3; ++o) d[ax][o] = (o - st.fx[ax]) * dx;
  const simd4 c2[3] = {a2 * d[2][0], a2 * d[2][1], a2 * d[2][2]};
  for (int a = 0; a < 3; ++a) {
    const simd4 base_a = base + a0 * d[0][a];
    for (int b = 0; b < 3; ++b) {
      const double wab = st.w[0][a] * st.w[1][b];
      const simd4 base_ab = base_a + a1 * d[1][b];
      double* row = &g[(st.base[0] + a) * si + (st.base[1] + b) * sj + st.base[2]].mv[0];
      for (int c = 0; c < 3; ++c) {
        simd4 node;
        load4(node, row + 4 * c);
        node += (wab * st.w[2][c]) * (base_ab + c2[c]);
        store4(row + 4 * c, node);
      }
    }
  }
}

// The particles order[begin, end) of one block, in order (the hot loop: one clone per ISA).
NSF_CLONES void scatter_block(const Particles& P, const uint32_t* order, uint32_t begin,
                              uint32_t end, Transfer transfer, double dt, double Dinv, double dx,
                              double inv_dx, const Vec3& lo, GridNode* g, size_t si, size_t sj) {
  for (uint32_t q = begin; q < end; ++q) {
    const uint32_t p = order[q];
    const Stencil st = quadratic_stencil(P.x[p], lo, inv_dx);
    const double m = P.mass[p];
    Mat3 Cp;
    switch (transfer) {
      case Transfer::APIC:
        Cp = P.C[p];
        break;
      case Transfer::RPIC:
        Cp = 0.5 * (P.C[p] - P.C[p].transpose());
        break;
      default:
        Cp = Mat3::Zero();
    }
    const Mat3 A = m * Cp - (dt * P.vol0[p] * Dinv) * P.tau[p];
    scatter_particle(st, dx, m * P.v[p], m, A, g, si, sj);
  }
}

}  // namespace

void Simulation::p2g(double dt) {
  ScopedTimer timer(times_.p2g);
  Particles& P = scene_.particles;
  const double dx = grid_.dx(), inv_dx = grid_.inv_dx();
  const double Dinv = apic_scale(inv_dx);
  const Transfer transfer = scene_.settings.transfer;
  const Vec3 lo = grid_.lo();
  const Vec3i n = grid_.dims();
  const size_t sj = n[2], si = size_t(n[1]) * n[2];
  GridNode* g = grid_.data();

  // One thread team for the clear and all eight colours: the colours still need a barrier
  // between them, but not a fork/join each, which is what costs most when the CPU is
  // oversubscribed.
  const auto clear_and_scatter = [&] {
    clear_active_grid();
    // Blocks of one colour never touch the same node, so they scatter in parallel without locks;
    // the implicit barrier at the end of each `omp for` keeps the colours apart.
    for (const auto& blocks : color_blocks_) {
#pragma omp for schedule(dynamic, 1)
      for (long bi = 0; bi < long(blocks.size()); ++bi) {
        const uint32_t b = blocks[bi];
        scatter_block(P, order_.data(), block_start_[b], block_start_[b + 1], transfer, dt, Dinv,
                      dx, inv_dx, lo, g, si, sj);
      }
    }
  };
  // On one thread, no team at all: the `omp for` loops then run in order without barriers, where
  // libgomp wakes a futex at every barrier even in a team of one (nine system calls a step, 4 % of
  // the ROM's step on metal_small). The same iterations in the same order: the same sums.
  if (omp_get_max_threads() > 1) {
#pragma omp parallel
    clear_and_scatter();
  } else {
    clear_and_scatter();
  }
}

}  // namespace nsf
