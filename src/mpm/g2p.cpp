// G2P (§3.3 step 3): gather velocity and its affine part, advect, update the trial F.
// With the MLS gradient, Σ_i v_i ∇w_ipᵀ = C_p, so F^trial = (I + Δt C_p) F^E.
#include "mpm/bspline.h"
#include "mpm/simulation.h"

namespace nsf {

void Simulation::g2p() {
  ScopedTimer timer(times_.g2p);
  Particles& P = scene_.particles;
  const double dx = grid_.dx(), inv_dx = grid_.inv_dx(), dt = scene_.settings.dt;
  const double Dinv = apic_scale(inv_dx);
  const Vec3 lo = grid_.lo();
  const Vec3i n = grid_.dims();
  const size_t sj = n[2], si = size_t(n[1]) * n[2];
  const GridNode* g = grid_.data();
  const long np = long(P.size());

#pragma omp parallel for schedule(static)
  for (long p = 0; p < np; ++p) {
    const Stencil st = quadratic_stencil(P.x[p], lo, inv_dx);
    Vec3 v = Vec3::Zero();
    Mat3 B = Mat3::Zero();
    for (int a = 0; a < 3; ++a) {
      const double da = (a - st.fx[0]) * dx;
      for (int b = 0; b < 3; ++b) {
        const double wab = st.w[0][a] * st.w[1][b];
        const double db = (b - st.fx[1]) * dx;
        const GridNode* row = g + (st.base[0] + a) * si + (st.base[1] + b) * sj + st.base[2];
        for (int c = 0; c < 3; ++c) {
          const double w = wab * st.w[2][c];
          const double dc = (c - st.fx[2]) * dx;
          const Vec3 vi(row[c].mv[0], row[c].mv[1], row[c].mv[2]);
          const Vec3 wv = w * vi;
          v += wv;
          B.col(0) += wv * da;
          B.col(1) += wv * db;
          B.col(2) += wv * dc;
        }
      }
    }
    const Mat3 C = Dinv * B;
    P.v[p] = v;
    P.C[p] = C;
    P.x[p] += dt * v;
    P.F[p] = (Mat3::Identity() + dt * C) * P.F[p];
  }
}

}  // namespace nsf
