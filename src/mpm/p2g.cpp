// P2G (§3.3 step 1), with the stress force of step 2 fused in (MLS-MPM, Hu et al. 2018):
// with ∇w_ip = w_ip · D⁻¹ (x_i − x_p), D⁻¹ = 4/Δx², the force −V⁰ τ ∇w_ip is an affine term,
// so momentum and force reach node i in one scatter:
//   m_i v_i += w_ip [ m_p v_p + (m_p C_p − Δt V⁰ D⁻¹ τ_p)(x_i − x_p) ].
#include "mpm/bspline.h"
#include "mpm/simulation.h"

namespace nsf {

void Simulation::p2g() {
  ScopedTimer timer(times_.p2g);
  clear_active_grid();
  Particles& P = scene_.particles;
  const double dx = grid_.dx(), inv_dx = grid_.inv_dx(), dt = scene_.settings.dt;
  const double Dinv = apic_scale(inv_dx);
  const Transfer transfer = scene_.settings.transfer;
  const Vec3 lo = grid_.lo();
  const Vec3i n = grid_.dims();
  const size_t sj = n[2], si = size_t(n[1]) * n[2];
  GridNode* g = grid_.data();

  // Blocks of one colour never touch the same node, so they scatter in parallel without locks.
  for (const auto& blocks : color_blocks_) {
#pragma omp parallel for schedule(dynamic, 1)
    for (long bi = 0; bi < long(blocks.size()); ++bi) {
      const uint32_t b = blocks[bi];
      for (uint32_t q = block_start_[b]; q < block_start_[b + 1]; ++q) {
        const uint32_t p = order_[q];
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
        const Vec3 mv = m * P.v[p];
        for (int a = 0; a < 3; ++a) {
          const double wa = st.w[0][a];
          const double da = (a - st.fx[0]) * dx;
          for (int bb = 0; bb < 3; ++bb) {
            const double wab = wa * st.w[1][bb];
            const double db = (bb - st.fx[1]) * dx;
            const Vec3 base_mom = mv + A.col(0) * da + A.col(1) * db;
            GridNode* row = g + (st.base[0] + a) * si + (st.base[1] + bb) * sj + st.base[2];
            for (int c = 0; c < 3; ++c) {
              const double w = wab * st.w[2][c];
              const double dc = (c - st.fx[2]) * dx;
              const Vec3 mom = base_mom + A.col(2) * dc;
              GridNode& node = row[c];
              node.mv[0] += w * mom[0];
              node.mv[1] += w * mom[1];
              node.mv[2] += w * mom[2];
              node.m += w * m;
            }
          }
        }
      }
    }
  }
}

}  // namespace nsf
