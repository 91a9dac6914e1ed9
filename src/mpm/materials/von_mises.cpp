#include "mpm/materials/von_mises.h"

#include "core/svd3.h"
#include "mpm/materials/hencky.h"
#include "mpm/materials/param_check.h"
#include "mpm/materials/principal.h"

namespace nsf {

MaterialPoint VonMises::make_point(const ParamMap& params, const std::string& path) const {
  ParamReader r(params, path, parameter_names());
  MaterialPoint mp = r.elastic_point();
  mp.yield_stress = r.get("yield_stress", positive_range());
  mp.hardening = r.get("hardening", 0.0, json::non_negative());
  mp.softening = r.get("softening", 0.0, json::non_negative());
  return mp;
}

// Norm convention: the yield condition of App. F.4 is ‖dev τ‖_F ≤ τ_y, the plain Frobenius norm
// (no √(3/2) "equivalent stress" factor). Since dev τ = 2μ ε̂, that is ‖ε̂‖ ≤ τ_y / 2μ, which is
// exactly what δγ = ‖ε̂‖ − τ_y/2μ measures; the projection keeps tr ε and scales ε̂ to length
// τ_y/2μ, so the returned stress lies on the cylinder up to rounding.
Mat3 VonMises::update(Mat3& F, MaterialPoint& mp, double /*dt*/) const {
  if (mp.damaged != 0.0) return Mat3::Zero();  // fractured: carries no stress, F is left as is
  Mat3 U, V;
  Vec3 s;
  svd3(F, U, s, V);
  Vec3 eps = hencky::log_strain(s);
  const Vec3 eps_hat = eps - Vec3::Constant(eps.sum() / 3.0);
  const double eps_hat_norm = eps_hat.norm();
  const double delta_gamma = eps_hat_norm - mp.yield_stress / (2.0 * mp.mu);
  if (delta_gamma > 0.0) {
    eps -= (delta_gamma / eps_hat_norm) * eps_hat;
    F = from_singular(U, eps.array().exp().matrix(), V);
    // ‖ε − proj(ε)‖ = δγ, so hardening and softening both move τ_y linearly in δγ.
    mp.yield_stress += (2.0 * mp.mu * mp.hardening - mp.softening) * delta_gamma;
    if (mp.yield_stress <= 0.0) {
      mp.yield_stress = 0.0;
      mp.mu = mp.lambda = 0.0;
      mp.damaged = 1.0;
      return Mat3::Zero();
    }
  }
  return from_principal(U, hencky::principal_kirchhoff(eps, mp.mu, mp.lambda));
}

}  // namespace nsf
