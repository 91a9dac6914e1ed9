#pragma once
// Hand-built scenes for engine tests, independent of the JSON scene loader.
#include <cmath>

#include "mpm/materials/material.h"
#include "mpm/scene/scene.h"

namespace nsf::testing {

// A box of ppc^3 particles per cell between lo and hi (cell-aligned), fixed corotated.
inline Scene box_scene(const Vec3& lo, const Vec3& hi, double dx, double dt, double E, double nu,
                       double rho, int ppc = 2) {
  Scene s;
  s.name = "test_box";
  s.settings.dx = dx;
  s.settings.dt = dt;
  s.settings.ppc = ppc;
  s.settings.density = rho;
  s.materials.push_back(make_material("fixed_corotated"));
  MaterialPoint mp = s.materials[0]->make_point({{"E", E}, {"nu", nu}}, "test");
  const double h = dx / ppc;
  const double V = h * h * h;
  Vec3i cnt = ((hi - lo) / h).array().round().cast<int>();
  for (int i = 0; i < cnt[0]; ++i)
    for (int j = 0; j < cnt[1]; ++j)
      for (int k = 0; k < cnt[2]; ++k) {
        Vec3 X = lo + (Vec3(i, j, k) + Vec3::Constant(0.5)) * h;
        s.particles.add(X, Vec3::Zero(), rho * V, V, mp, 0, 0);
      }
  return s;
}

inline double total_mass(const Particles& P) {
  double m = 0;
  for (size_t p = 0; p < P.size(); ++p) m += P.mass[p];
  return m;
}

inline Vec3 linear_momentum(const Particles& P) {
  Vec3 L = Vec3::Zero();
  for (size_t p = 0; p < P.size(); ++p) L += P.mass[p] * P.v[p];
  return L;
}

// APIC angular momentum about the origin: Σ m (x × v) plus the affine part
// m·(Δx²/4)·(C₂₁ − C₁₂, C₀₂ − C₂₀, C₁₀ − C₀₁) that the affine velocity field carries
// (Jiang et al. 2015; derived from Σ_i w_ip (x_i − x_p)(x_i − x_p)ᵀ = Δx²/4 I).
inline Vec3 angular_momentum(const Particles& P, double dx, bool with_affine) {
  Vec3 L = Vec3::Zero();
  const double D = dx * dx / 4.0;
  for (size_t p = 0; p < P.size(); ++p) {
    L += P.mass[p] * P.x[p].cross(P.v[p]);
    if (with_affine) {
      const Mat3& C = P.C[p];
      L += P.mass[p] * D * Vec3(C(2, 1) - C(1, 2), C(0, 2) - C(2, 0), C(1, 0) - C(0, 1));
    }
  }
  return L;
}

}  // namespace nsf::testing
