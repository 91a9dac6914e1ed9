#pragma once
// Settings of the Gauss–Newton fit of a latent to positions (nn/latent_inversion.h), free of
// torch types: the reduced-order step (rom/rom_options.h) and training's latent refinement
// share them.

namespace nsf {

class LatentPrior;

struct GaussNewtonOptions {
  int max_iterations = 3;   // the paper converges in 2–3
  double tolerance = 1e-5;  // stop when ‖Δẑ‖ ≤ tolerance · (1 + ‖ẑ‖)
  bool taylor = false;      // one linearised step at ẑ_n (first-order Taylor, Chen et al. 2023a)
  // BLAS threads of the fit (0 = those of the rest of the step). Its GEMMs are |S| points wide,
  // a few hundred, too small to split across threads (docs/experiments/2026-11-23-gn-threads.md).
  int threads = 1;
  // A pull toward the latents h and l were trained on (nn/latent_prior.h): the fit minimises
  // Σ_S ‖g(X_p, ẑ) − x_p‖² + |S| ε² d(ẑ)², d the distance to the training runs' latent surface
  // in training spreads, so one spread off it costs as much as every sample ε (m) out of place.
  // No prior or ε = 0: the paper's fit.
  const LatentPrior* prior = nullptr;
  double prior_length = 0;  // ε
};

}  // namespace nsf
