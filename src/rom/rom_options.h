#pragma once
// Settings of the reduced-order simulator (docs/ROM.md), free of torch types.
#include <cstddef>
#include <string>
#include <vector>

#include "nn/gauss_newton.h"
#include "rom/step/sampling.h"

namespace nsf {

// Where the step's fields come from, by source name (rom/fields/field_source.h; `nsf rom --help`
// and docs/ROM.md, "Field sources", list them). Empty: the model's own decoders ("network" for the
// paper's MLP fields, "basis" for per-point bases), and for C, "none" when the stress is CROM's
// (the baseline has no affine field).
struct FieldChoice {
  std::string deformation;  // g on the candidates: network, basis
  std::string stress;       // τ on N: network, basis, crom, tracked
  std::string affine;       // C on N: network, basis, none, tracked
  std::string velocity;     // v on N: latent (g's backward difference, the paper), tracked
};

struct RomOptions {
  // ROM step over the scene's Δt, rounded so that a frame is a whole number of ROM steps; a
  // scene's "rom" section may set its own (rom/setup/rom_section.h). The paper uses 1.5. What suits
  // a scene is measured, not derived: on metal_small 1.5 gave δ 3.3 %, 1.0 gave 1.5 %; on the
  // paper-size sand 4 gives 3.6 % against 5.2 % at 1.0
  // (docs/experiments/2026-11-25-larger-rom-steps.md). kDtRatioAtCfl: the largest step within the
  // CFL bound (`cfl` below, else the scene's; the fastest particle's start speed added to the
  // wave speed), so that a scene made stiffer or finer keeps a
  // stable step without a new ratio.
  double dt_ratio = 1.0;
  static constexpr double kDtRatioAtCfl = 0;
  SamplingSpec sampling;
  GaussNewtonOptions inversion;
  FieldChoice fields;
  // > 0: the inversion's latent prior (rom/inversion/latent_prior.h) with this ε in metres
  // (GaussNewtonOptions::penalty_length), built from the latents the model stores of its training
  // runs. 0: none (the paper).
  double latent_prior = 0;
  int halo = 3;  // candidate margin in cells around I (rom/step/integration_set.h)
  // > 0: the MPM step on N integrates with this many points per grid cell of the rest shape, each
  // merging a group of particles (rom/step/quadrature.h); N, K and the inference on them shrink by
  // the thinning factor. 0: every particle (the paper).
  int quadrature_per_cell = 0;
  // > 0: the CFL factor the tracked state's explicit step is held to (the step's bound is
  // cfl · Δx / wave speed), in place of the scene's simulation.cfl, which bounds full order's.
  double cfl = 0;
  // The ROM's grid spacing over the scene's Δx (≥ 1): the MPM step on N, its transfers and its CFL
  // bound use a grid this many times coarser; the particles, g and the samples are the scene's.
  double grid_factor = 1;
  // The scene objects (indices into its objects) that move in rigid frames of their own over the
  // latent manifold (rom/step/rigid_frames.h): x = R (g − c) + c + t, R and t fitted beside ẑ.
  // Empty: none, the paper's reduced step.
  std::vector<int> rigid_frames;
  // A step over fewer candidate points than this runs on one thread: its parallel loops are too
  // small for a second thread to pay for waking up (docs/ROM.md). 0: always on every thread.
  size_t serial_below_points = 8192;

  // The sources by name, with the defaults filled in for a model whose decoders are `decoder`.
  FieldChoice resolved_fields(const std::string& decoder) const {
    FieldChoice f = fields;
    if (f.deformation.empty()) f.deformation = decoder;
    if (f.affine.empty()) f.affine = f.stress == "crom" ? "none" : decoder;
    if (f.stress.empty()) f.stress = decoder;
    if (f.velocity.empty()) f.velocity = "latent";
    return f;
  }
};

}  // namespace nsf
