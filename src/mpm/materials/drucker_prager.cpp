#include "mpm/materials/drucker_prager.h"

#include <cmath>

#include "core/svd3.h"
#include "mpm/materials/hencky.h"
#include "mpm/materials/param_check.h"
#include "mpm/materials/principal.h"

namespace nsf {

MaterialPoint DruckerPrager::make_point(const ParamMap& params, const std::string& path) const {
  ParamReader r(params, path, parameter_names());
  MaterialPoint mp = r.elastic_point();
  double phi = r.get("friction_angle", {0.0, 90.0, true, true});
  double cohesion = r.get("cohesion", 0.0, json::non_negative());
  const double sin_phi = std::sin(phi * M_PI / 180.0);
  mp.alpha = std::sqrt(2.0 / 3.0) * 2.0 * sin_phi / (3.0 - sin_phi);  // App. F.3
  mp.cohesion = cohesion;
  return mp;
}

// Return map Z(Σ) of App. F.3 in log-strain space. On the cone, with dev τ = 2μ ε̂ and
// tr τ = (dλ + 2μ) tr ε, δγ = 0 is exactly ‖dev τ‖ + α tr τ = 0; the projection only shrinks ε̂
// (keeping tr ε), so the result lands on that surface by construction.
Mat3 DruckerPrager::update(Mat3& F, MaterialPoint& mp, double /*dt*/) const {
  constexpr double d = 3.0;
  Mat3 U, V;
  Vec3 s;
  svd3(F, U, s, V);
  const Vec3 eps = hencky::log_strain(s) - Vec3::Constant(mp.cohesion);
  const double tr = eps.sum();
  if (tr > 0.0) {
    // Expansion: F^E goes to the cone tip. Without cohesion the grains separate and carry no
    // stress; with it the tip is the isotropic stretch e^cohesion and its (tensile) Hencky stress.
    F = std::exp(mp.cohesion) * (U * V.transpose());
    if (mp.cohesion == 0.0) return Mat3::Zero();
    return hencky::principal_kirchhoff(Vec3::Constant(mp.cohesion), mp.mu, mp.lambda)[0] *
           Mat3::Identity();
  }
  const Vec3 eps_hat = eps - Vec3::Constant(tr / d);
  const double eps_hat_norm = eps_hat.norm();
  const double delta_gamma =
      eps_hat_norm + mp.alpha * (d * mp.lambda + 2.0 * mp.mu) * tr / (2.0 * mp.mu);
  Vec3 eps_e = eps + Vec3::Constant(mp.cohesion);
  if (delta_gamma > 0.0) {
    // δγ > 0 implies ‖ε̂‖ > 0 (tr ε ≤ 0 here), so the division is safe.
    eps_e -= (delta_gamma / eps_hat_norm) * eps_hat;
    F = from_singular(U, eps_e.array().exp().matrix(), V);
  }
  return from_principal(U, hencky::principal_kirchhoff(eps_e, mp.mu, mp.lambda));
}

}  // namespace nsf
