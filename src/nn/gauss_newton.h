#pragma once
// Settings of the Gauss–Newton fit of a latent to positions (nn/latent_inversion.h), free of
// torch types: the reduced-order step (rom/rom_options.h) and training's latent refinement
// share them.
#include <Eigen/Core>

namespace nsf {

// A penalty d(ẑ)² on the latent that the fit adds to the samples' misfit, with the terms the
// Gauss–Newton step needs at ẑ. What it measures is its owner's: the ROM's latent prior
// (rom/inversion/latent_prior.h), the distance to the training runs' latents, is one.
class LatentPenalty {
 public:
  struct Terms {
    double distance2 = 0;      // d(ẑ)²
    Eigen::VectorXd gradient;  // ½ ∂d²/∂ẑ
    Eigen::MatrixXd hessian;   // ½ ∂²d²/∂ẑ², Gauss–Newton's (of d linearised at ẑ)
  };
  virtual ~LatentPenalty() = default;
  virtual Terms terms(const Eigen::VectorXd& z) const = 0;
};

struct GaussNewtonOptions {
  int max_iterations = 3;   // the paper converges in 2–3
  double tolerance = 1e-5;  // stop when ‖Δẑ‖ ≤ tolerance · (1 + ‖ẑ‖)
  bool taylor = false;      // one linearised step at ẑ_n (first-order Taylor, Chen et al. 2023a)
  // BLAS threads of the fit (0 = those of the rest of the step). Its GEMMs are |S| points wide,
  // a few hundred, too small to split across threads (docs/experiments/2026-11-23-gn-threads.md).
  int threads = 1;
  // A penalty on the latent: the fit minimises Σ_S ‖g(X_p, ẑ) − x_p‖² + |S| ε² d(ẑ)², so that
  // d = 1 costs as much as every sample ε (m) out of place. No penalty or ε = 0: the paper's fit.
  const LatentPenalty* penalty = nullptr;
  double penalty_length = 0;  // ε
  // Levenberg–Marquardt damping λ: λ·diag(JᵀJ) joins the normal equations, which shortens the step
  // along directions the samples barely tell apart (a latent direction and a rigid frame's that
  // move them alike, rom/step/rigid_frames.h). 0: plain Gauss–Newton.
  double damping = 0;
};

}  // namespace nsf
