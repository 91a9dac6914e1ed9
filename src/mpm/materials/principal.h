#pragma once
// Isotropic models have a Kirchhoff stress that shares the eigenvectors of b = F Fᵀ, i.e. the left
// singular vectors U of F: τ = U diag(t) Uᵀ. Models compute the three principal values t and
// rotate once, which is cheaper than matrix formulas and symmetric by construction.
#include "core/types.h"

namespace nsf {

inline Mat3 from_principal(const Mat3& U, const Vec3& t) {
  return U * t.asDiagonal() * U.transpose();
}

// F = U diag(sigma) Vᵀ: rebuilds a deformation gradient after a return map changed its stretches.
inline Mat3 from_singular(const Mat3& U, const Vec3& sigma, const Mat3& V) {
  return U * sigma.asDiagonal() * V.transpose();
}

}  // namespace nsf
