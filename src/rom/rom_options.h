#pragma once
// Settings of the reduced-order simulator (docs/ROM.md), free of torch types.
#include "rom/sampling.h"

namespace nsf {

class LatentPrior;

struct GaussNewtonOptions {
  int max_iterations = 3;   // the paper converges in 2–3
  double tolerance = 1e-5;  // stop when ‖Δẑ‖ ≤ tolerance · (1 + ‖ẑ‖)
  bool taylor = false;      // one linearised step at ẑ_n (first-order Taylor, Chen et al. 2023a)
  // BLAS threads of the fit (0 = those of the rest of the step). Its GEMMs are |S| points wide,
  // a few hundred, too small to split across threads (docs/ROM.md, "Threads of the inversion").
  int threads = 1;
  // A pull toward the latents h and l were trained on (rom/latent_prior.h): the fit minimises
  // Σ_S ‖g(X_p, ẑ) − x_p‖² + |S| ε² d(ẑ)², d the distance to the training runs' latent surface
  // in training spreads, so one spread off it costs as much as every sample ε (m) out of place.
  // No prior or ε = 0: the paper's fit.
  const LatentPrior* prior = nullptr;
  double prior_length = 0;  // ε
};

// Where the ROM step takes the particles' APIC affine matrices C from.
enum class AffineSource {
  network,  // l(X, ẑ) (§4.4, the paper)
  velocity,  // the ROM's own velocity field: C = Ḟ F⁻¹ with F = ∂g/∂X at ẑ_n, Ḟ its difference
             // quotient from ẑ_{n−1}; APIC's C is the velocity gradient at the particle
  none,     // C = 0 (the CROM baseline's default)
  tracked,  // each particle keeps the C its last G2P gave it, as the full-order engine does
            // (needs every particle a sample; an ablation of l, docs/ROM.md)
};

// Where the ROM step takes the particles' Kirchhoff stress τ from.
enum class StressSource {
  network,  // h(X, ẑ[, μ]) (§4.3, the paper)
  // Each particle carries F^E and its plastic state, updated through the scene's constitutive
  // model from the velocity gradient of its own G2P, as in the full-order engine; the ROM's
  // positions still come from g. Needs every particle a sample: an ablation of h that says
  // how much of the ROM's error is h's (docs/ROM.md, "Where the ROM's error comes from").
  tracked,
};

struct RomOptions {
  // ROM step over the scene's Δt, rounded so that a frame is a whole number of ROM steps; a
  // scene's "rom" section may set its own (rom/rom_section.h). The paper uses 1.5. What suits a
  // scene is measured, not derived: on metal_small 1.5 gave δ 3.3 %, 1.0 gave 1.5 %; on the
  // paper-size sand 4 gives 3.6 % against 5.2 % at 1.0 (docs/ROM.md, "Larger ROM steps").
  double dt_ratio = 1.0;
  // Share of the transfer's smoothing loss given back to the sample particles each step
  // (FLIP-style: x_S += Δt · flip · (v_S − the velocity P2G then G2P alone hands back)).
  // 0: the engine's APIC step as it stands (the paper).
  double flip = 0.0;
  SamplingSpec sampling;
  GaussNewtonOptions inversion;
  // CROM-style baseline (Figs. 5, 12, 13): τ from F = ∂g/∂X through the constitutive model,
  // no affine field (C = 0); h and l are not used.
  bool crom = false;
  // Network by default, none when `crom` is set; the CROM baseline can also take `velocity`.
  AffineSource affine = AffineSource::network;
  StressSource stress = StressSource::network;
  // The affine source a run uses: `affine`, except that the baseline has no affine network, so
  // there `network` means its default, none.
  AffineSource resolved_affine() const {
    return crom && affine == AffineSource::network ? AffineSource::none : affine;
  }
  // > 0: the tangent cache (rom/linearized_field.h): g, h and l through per-particle first-order
  // expansions in ẑ, recomputed when ẑ moves further than this from their anchor (in units of
  // each latent component's training spread). 0: the networks at every step, as in the paper.
  double linearize = 0;
  // > 0: the inversion's latent prior with this ε in metres (GaussNewtonOptions::prior_length),
  // built from the latents the model stores of its training runs. 0: none (the paper).
  double latent_prior = 0;
  int halo = 3;  // candidate margin in cells around I (rom/integration_set.h)
  // > 0: the MPM step on N integrates with this many points per grid cell of the rest shape, each
  // merging a group of particles (rom/quadrature.h); N, K and the inference on them shrink by
  // the thinning factor. 0: every particle (the paper).
  int quadrature_per_cell = 0;
  // Also find N by brute force (g on every particle) each step and count the particles the
  // candidate scheme missed. For tests and checks; costs a full evaluation of g per step.
  bool verify_integration_set = false;
};

}  // namespace nsf
