#include "mpm/materials/fixed_corotated.h"

#include "core/polar3.h"
#include "core/svd3.h"
#include "mpm/materials/param_check.h"
#include "mpm/materials/principal.h"

namespace nsf {

MaterialPoint FixedCorotated::make_point(const ParamMap& params, const std::string& path) const {
  ParamReader r(params, path, parameter_names());
  MaterialPoint mp = r.elastic_point();
  return mp;
}

Mat3 FixedCorotated::update(Mat3& F, MaterialPoint& mp, double /*dt*/) const {
  // Fast path: the stress needs only R and J, and for the near-rotation F of a typical step the
  // Newton polar iteration gives them ~5× cheaper than a full SVD (core/polar3.h).
  Mat3 R;
  double J;
  if (fast_polar_rotation(F, R, J)) {
    // (F − R)Fᵀ = R (S − 1) S Rᵀ is symmetric; symmetrising removes the rounding asymmetry, so
    // the stress force keeps conserving angular momentum exactly as the SVD form does.
    const Mat3 P = (F - R) * F.transpose();
    Mat3 tau = mp.mu * (P + P.transpose());
    tau.diagonal().array() += mp.lambda * (J - 1.0) * J;
    return tau;
  }
  // Inverted, degenerate or strongly distorted F: the robust SVD.
  Mat3 U, V;
  Vec3 s;
  svd3(F, U, s, V);
  // Eq. (12) in principal form: with R = U Vᵀ, (F − R)Fᵀ = U (Σ − 1)Σ Uᵀ. J = σ0σ1σ2 keeps the
  // sign of det F, so the volume term still pushes inverted particles back.
  J = s.prod();
  const Vec3 t =
      2.0 * mp.mu * (s - Vec3::Ones()).cwiseProduct(s) + Vec3::Constant(mp.lambda * (J - 1.0) * J);
  return from_principal(U, t);
}

}  // namespace nsf
