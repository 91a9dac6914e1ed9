#include "mpm/materials/herschel_bulkley.h"

#include <algorithm>
#include <cmath>

#include "core/svd3.h"
#include "mpm/materials/param_check.h"
#include "mpm/materials/principal.h"

namespace nsf {

MaterialPoint HerschelBulkley::make_point(const ParamMap& params, const std::string& path) const {
  ParamReader r(params, path, parameter_names());
  MaterialPoint mp = r.elastic_point();
  mp.yield_stress = r.get("yield_stress", json::non_negative());
  mp.viscosity = r.get("viscosity", json::non_negative());
  return mp;
}

namespace {

// Keeps the isochoric part b̄ = J^(−2/3) b defined for a collapsed particle (J → 0); no
// physical state comes near it.
constexpr double kMinJ = 1e-12;

// The c with (a0 + c)(a1 + c)(a2 + c) = 1, given sum(a) = 0: the isotropic part that makes
// b̄ = diag(a) + c·1 isochoric again after its deviatoric part a was shrunk. f(c) = ∏(a_i + c) is
// increasing and convex where all factors are positive, and f(c0) ≥ 1 at the trial value c0 (the
// trial b̄ had det 1 and a larger deviator), so Newton from c0 decreases monotonically to the root.
double isochoric_shift(const Vec3& a, double c0) {
  double c = c0;
  for (int it = 0; it < 50; ++it) {
    const Vec3 x = a + Vec3::Constant(c);
    const double f = x.prod() - 1.0;
    const double df = x[1] * x[2] + x[0] * x[2] + x[0] * x[1];
    const double step = f / df;
    c -= step;
    if (std::abs(step) <= 1e-15 * c) break;
  }
  return c;
}

}  // namespace

// Works in the principal frame of b^E = F Fᵀ = U Σ² Uᵀ: b̄ = J^(−2/3) b and dev τ keep the
// eigenvectors U, so the return map only changes the three principal values, and F^E is rebuilt
// as U Σ' Vᵀ with the trial rotation U Vᵀ and volume J kept (plastic flow is isochoric).
Mat3 HerschelBulkley::update(Mat3& F, MaterialPoint& mp, double dt) const {
  Mat3 U, V;
  Vec3 s;
  svd3(F, U, s, V);
  const double J = s.prod();
  const double J_abs = std::max(std::abs(J), kMinJ);
  const double mu = mp.mu;
  const double kappa = mp.lambda + 2.0 * mu / 3.0;  // = E / 3(1 − 2ν)

  Vec3 b_bar = std::pow(J_abs, -2.0 / 3.0) * s.cwiseProduct(s);
  const double trial_mean = b_bar.mean();
  Vec3 a = b_bar - Vec3::Constant(trial_mean);  // dev b̄ = s^trial / μ
  const double s_trial = mu * a.norm();
  const double s_yield = std::sqrt(2.0 / 3.0) * mp.yield_stress;
  if (s_trial > s_yield) {
    // s = s^tr − (s^tr − √(2/3)σ_Y) / (1 + η / 2μΔt), written so that Δt = 0 or η = 0 is exact.
    const double relax = 2.0 * mu * dt / (2.0 * mu * dt + mp.viscosity);
    const double s_new = s_trial - (s_trial - s_yield) * relax;
    a *= s_new / s_trial;
    b_bar = a + Vec3::Constant(isochoric_shift(a, trial_mean));
    // Σ' = J^(1/3) √b̄ with the trial signs, so det F^E = J exactly (inversion is kept, not hidden).
    const double cbrt_J = std::cbrt(J_abs);
    Vec3 stretch;
    for (int i = 0; i < 3; ++i) stretch[i] = std::copysign(cbrt_J * std::sqrt(b_bar[i]), s[i]);
    F = from_singular(U, stretch, V);
  }
  // τ = κ/2 (J² − 1) I + μ dev(b̄), App. F.5.
  const Vec3 t =
      Vec3::Constant(0.5 * kappa * (J * J - 1.0)) + mu * (b_bar - Vec3::Constant(b_bar.mean()));
  return from_principal(U, t);
}

}  // namespace nsf
