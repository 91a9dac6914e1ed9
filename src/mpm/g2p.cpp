// G2P (§3.3 step 3): gather velocity and its affine part, advect, update the trial F.
// With the MLS gradient, Σ_i v_i ∇w_ipᵀ = C_p, so F^trial = (I + Δt C_p) F^E.
#include "core/parallel_for.h"
#include "mpm/bspline.h"
#include "mpm/simulation.h"

namespace nsf {

namespace {

using Vec4 = Eigen::Matrix<double, 4, 1>;

// v = Σ w_ip v_i and B = Σ w_ip v_i (x_i − x_p)ᵀ over the 27 stencil nodes. Each node is read as
// one 4-wide vector (velocity plus the unused mass lane). Along the innermost axis the sums
// Σ_c w_c v_i and Σ_c w_c d_c v_i are formed first, so the (a, b) offsets multiply 9 partial sums
// rather than 27 node values.
inline void gather_particle(const Stencil& st, double dx, const GridNode* g, size_t si, size_t sj,
                            Vec3& v, Mat3& B) {
  double d[3][3];
  for (int ax = 0; ax < 3; ++ax)
    for (int o = 0; o < 3; ++o) d[ax][o] = (o - st.fx[ax]) * dx;
  const double wc[3] = {st.w[2][0], st.w[2][1], st.w[2][2]};
  const double wdc[3] = {wc[0] * d[2][0], wc[1] * d[2][1], wc[2] * d[2][2]};
  Vec4 sv = Vec4::Zero(), s0 = Vec4::Zero(), s1 = Vec4::Zero(), s2 = Vec4::Zero();
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      const double* row = &g[(st.base[0] + a) * si + (st.base[1] + b) * sj + st.base[2]].mv[0];
      const Eigen::Map<const Vec4> n0(row), n1(row + 4), n2(row + 8);
      const Vec4 rv = wc[0] * n0 + wc[1] * n1 + wc[2] * n2;
      const Vec4 rd = wdc[0] * n0 + wdc[1] * n1 + wdc[2] * n2;
      const double wab = st.w[0][a] * st.w[1][b];
      const Vec4 wrv = wab * rv;
      sv += wrv;
      s0 += d[0][a] * wrv;
      s1 += d[1][b] * wrv;
      s2 += wab * rd;
    }
  }
  v = sv.head<3>();
  B.col(0) = s0.head<3>();
  B.col(1) = s1.head<3>();
  B.col(2) = s2.head<3>();
}

}  // namespace

void Simulation::g2p(double dt, const std::vector<uint32_t>* gather) {
  ScopedTimer timer(times_.g2p);
  Particles& P = scene_.particles;
  const double dx = grid_.dx(), inv_dx = grid_.inv_dx();
  const double Dinv = apic_scale(inv_dx);
  const Vec3 lo = grid_.lo();
  const Vec3i n = grid_.dims();
  const size_t sj = n[2], si = size_t(n[1]) * n[2];
  const GridNode* g = grid_.data();
  const long np = long(gather ? gather->size() : P.size());

  parallel_for(np, [&](long q) {
    const long p = gather ? long((*gather)[q]) : q;
    const Stencil st = quadratic_stencil(P.x[p], lo, inv_dx);
    Vec3 v;
    Mat3 B;
    gather_particle(st, dx, g, si, sj, v, B);
    const Mat3 C = Dinv * B;
    P.v[p] = v;
    P.C[p] = C;
    P.x[p] += dt * v;
    P.F[p] = (Mat3::Identity() + dt * C) * P.F[p];
  });
}

}  // namespace nsf
