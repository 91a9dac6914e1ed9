// G2P (§3.3 step 3): gather velocity and its affine part, advect, update the trial F.
// With the MLS gradient, Σ_i v_i ∇w_ipᵀ = C_p, so F^trial = (I + Δt C_p) F^E.
#include <algorithm>

#include "core/isa.h"
#include "core/parallel_for.h"
#include "mpm/bspline.h"
#include "mpm/simulation.h"

namespace nsf {

namespace {

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
  simd4 sv = {0, 0, 0, 0}, s0 = sv, s1 = sv, s2 = sv;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      const double* row = &g[(st.base[0] + a) * si + (st.base[1] + b) * sj + st.base[2]].mv[0];
      simd4 n0, n1, n2;
      load4(n0, row), load4(n1, row + 4), load4(n2, row + 8);
      const simd4 rv = wc[0] * n0 + wc[1] * n1 + wc[2] * n2;
      const simd4 rd = wdc[0] * n0 + wdc[1] * n1 + wdc[2] * n2;
      const double wab = st.w[0][a] * st.w[1][b];
      const simd4 wrv = wab * rv;
      sv += wrv;
      s0 += d[0][a] * wrv;
      s1 += d[1][b] * wrv;
      s2 += wab * rd;
    }
  }
  v = Vec3(sv[0], sv[1], sv[2]);
  B << s0[0], s1[0], s2[0], s0[1], s1[1], s2[1], s0[2], s1[2], s2[2];
}

struct G2PArgs {
  Particles* P;
  const std::vector<uint32_t>* gather;
  double dt, dx, inv_dx, Dinv;
  Vec3 lo;
  const GridNode* g;
  size_t si, sj;
};

// Particles [begin, end) of the list (the hot loop: one clone per ISA).
NSF_CLONES void gather_range(const G2PArgs& a, long begin, long end) {
  Particles& P = *a.P;
  for (long q = begin; q < end; ++q) {
    const long p = a.gather ? long((*a.gather)[size_t(q)]) : q;
    const Stencil st = quadratic_stencil(P.x[p], a.lo, a.inv_dx);
    Vec3 v;
    Mat3 B;
    gather_particle(st, a.dx, a.g, a.si, a.sj, v, B);
    const Mat3 C = a.Dinv * B;
    P.v[p] = v;
    P.C[p] = C;
    P.x[p] += a.dt * v;
    P.F[p] = (Mat3::Identity() + a.dt * C) * P.F[p];
  }
}

}  // namespace

void Simulation::g2p(double dt, const std::vector<uint32_t>* gather) {
  ScopedTimer timer(times_.g2p);
  Particles& P = scene_.particles;
  const Vec3i n = grid_.dims();
  G2PArgs a{&P,          gather,         dt,
            grid_.dx(),  grid_.inv_dx(), apic_scale(grid_.inv_dx()),
            grid_.lo(),  grid_.data(),   size_t(n[1]) * n[2],
            size_t(n[2])};
  const long np = long(gather ? gather->size() : P.size());
  // Chunks of 256 particles: one call of the chosen clone each.
  constexpr long kChunk = 256;
  parallel_for((np + kChunk - 1) / kChunk,
               [&](long c) { gather_range(a, c * kChunk, std::min(np, (c + 1) * kChunk)); });
}

}  // namespace nsf
