#pragma once
// `nsf eval`: how well a trained model reproduces held-out runs when each frame's latent comes
// from the encoder (no latent dynamics yet): δ of eq. (11) and relative errors of τ and C.
#include <cmath>
#include <string>
#include <vector>

#include "nn/held_out_points.h"

namespace nsf {

struct EvalOptions {
  std::string split = "test";  // "test", "train" or "all"
  size_t frame_stride = 1;     // every k-th frame (frames 1…N, as in eq. 11)
  size_t max_particles = 0;    // 0 = all; otherwise an evenly spaced subset (cheaper on big scenes)
  // > 0: refine each encoded latent by this many Gauss–Newton iterations on 1,024 evenly spaced
  // particles, as the ROM's inversion would (are h and l accurate on the latents the ROM sees?).
  int refine_iterations = 0;
  int poly_degree = 4;            // degree of the per-frame polynomial fits (poly columns)
  bool allow_incomplete = false;  // evaluate on a dataset an interrupted sweep left incomplete
  // > 0 (basis models): hold out every k-th particle and read its fields from the others'
  // through `interpolation` over `neighbours` particles (nn/held_out_points.h).
  size_t held_out_stride = 0;
  std::string interpolation = "mls";
  int neighbours = kInterpolationNeighbours;
};

struct EvalRow {
  std::string run;  // file name
  double mu = 0;
  bool has_mu = false;
  size_t frames = 0, particles = 0;
  double delta = 0;          // eq. (11): √(Σ‖g(X,ẑ_n) − x_n‖² / Σ‖x_n‖²)
  double delta_encoded = 0;  // the same at the encoder's latents (= delta unless refined)
  double stress_error = 0;  // √(Σ‖h − τ‖²_F / Σ‖τ‖²_F), full 3×3 Frobenius norms
  double affine_error = 0;  // same for l and C
  // Yardsticks (nn/field_checks.h): the stress error of the forces h puts on the grid, and the
  // residuals of the best per-frame polynomial of degree 4 in X per object, fitted to the
  // ground-truth τ and C: how much of each field is smooth at that scale. A field h(X, ẑ) that
  // resolves finer features can beat it; particle-scale noise stays in both.
  double force_error = 0;
  double stress_poly_fit = 0, affine_poly_fit = 0;
  // A basis model's own bound: the same frames projected onto its bases (the best any
  // coefficients can do), as δ and relative errors; NaN for an MLP model.
  double projection_delta = NAN, projection_stress = NAN, projection_affine = NAN;
  // With EvalOptions::held_out_stride: the held-out particles' errors (particles = 0 without).
  HeldOutErrors held_out;
};

std::vector<EvalRow> evaluate_model(const std::string& model_path, const std::string& data_dir,
                                    const EvalOptions& options);

}  // namespace nsf
