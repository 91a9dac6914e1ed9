#pragma once
// Fast rotation part of a 3×3 deformation gradient, F = R S, for the common MPM case: det F > 0
// and F close to a rotation (elastic strains of a few percent).
//
// Newton's iteration X ← ½(X + X⁻ᵀ) (Higham 1986) keeps the singular vectors of F and maps each
// singular value σ to ½(σ + 1/σ), so it converges to R = U Vᵀ with error (σ − 1)²/(2σ) per step.
// X⁻ᵀ is the cofactor matrix over det X (three cross products, one division), so a step is a few
// dozen flops with one division on the critical path: for strains ≲ 10% four or five steps take
// ~50 ns, against ~300 ns for the full SVD (bench/bench_svd.cpp).
//
// It returns false, and the caller falls back to the robust svd3(), whenever the fast path would
// not give the MPM convention's answer or not converge quickly: det F ≤ 0 (the iteration would
// converge to an improper orthogonal matrix, while the convention keeps R a rotation and puts the
// sign on σ2), near-singular or badly scaled F, or NaN/Inf.
#include <cmath>

#include "core/types.h"

namespace nsf {

namespace polar3_detail {
// ‖X_{k+1} − X_k‖ is ≈ the error of X_k, and the error of X_{k+1} is ≈ half its square, so
// stopping once the step is below 2e-8 leaves R within ~2e-16 of orthogonal: rounding level.
constexpr double kStepTol2 = 4e-16;
// σ ∈ [0.5, 2] converges in 6 steps; needing more means a strongly distorted F, where the robust
// SVD costs no more and is better behaved.
constexpr int kMaxSteps = 8;
// det F must be clearly positive and of moderate size: the cofactors square entries, and a tiny
// det means a near-singular F whose polar factor is ill determined.
constexpr double kMinDet = 1e-6;
constexpr double kMaxDet = 1e6;
}  // namespace polar3_detail

// On success sets R (rotation, det +1) and J = det F and returns true; returns false otherwise
// (R and J are then unspecified).
inline bool fast_polar_rotation(const Mat3& F, Mat3& R, double& J) {
  using namespace polar3_detail;
  Mat3 X = F;
  for (int step = 0; step < kMaxSteps; ++step) {
    Mat3 cof;
    cof.col(0) = X.col(1).cross(X.col(2));
    cof.col(1) = X.col(2).cross(X.col(0));
    cof.col(2) = X.col(0).cross(X.col(1));
    const double det = X.col(0).dot(cof.col(0));
    if (step == 0) {
      if (!(det > kMinDet && det < kMaxDet)) return false;  // also rejects NaN
      J = det;
    }
    const Mat3 next = 0.5 * X + (0.5 / det) * cof;
    const double step2 = (next - X).squaredNorm();
    X = next;
    if (step2 <= kStepTol2) {
      R = X;
      return true;
    }
  }
  return false;
}

}  // namespace nsf
