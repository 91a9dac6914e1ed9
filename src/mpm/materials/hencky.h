#pragma once
// StVK elasticity with Hencky (logarithmic) strain in principal space, App. F.2 [Klár et al. 2016].
// Shared by the elastic model and the Drucker–Prager and von Mises return maps, which project the
// same log strain ε = log Σ.
#include <algorithm>
#include <cmath>

#include "core/types.h"

namespace nsf::hencky {

// log 0 = −∞: a collapsed or inverted particle is already unphysical for this energy, the floor
// only keeps its stress finite (the value follows Ziran's StVK-Hencky models). Inversion is seen
// through |σ|, so this energy does not resist it.
constexpr double kMinStretch = 1e-4;

inline Vec3 log_strain(const Vec3& sigma) {
  return sigma.cwiseAbs().cwiseMax(kMinStretch).array().log().matrix();
}

// Principal Kirchhoff stress, eq. (13): τ_i = 2μ ε_i + λ sum(ε). The paper writes U(…)Vᵀ; with
// ψ = μ‖ε‖² + λ/2 (tr ε)² the first Piola stress is P = U Σ⁻¹(2με + λ tr ε 1) Vᵀ, so
// τ = P Fᵀ = U (2με + λ tr ε 1) Uᵀ [Klár et al. 2016]: symmetric, as τ must be.
inline Vec3 principal_kirchhoff(const Vec3& eps, double mu, double lambda) {
  return 2.0 * mu * eps + Vec3::Constant(lambda * eps.sum());
}

}  // namespace nsf::hencky
