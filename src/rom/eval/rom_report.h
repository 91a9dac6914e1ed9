#pragma once
// What a reduced-order run measured against full order (rom/eval/rom_evaluation.h): the setup it
// ran with, δ and the field errors against the truth, the budget, the baselines, time and memory;
// and its summary as `nsf rom` prints it.
#include <optional>
#include <string>
#include <vector>

#include "rom/eval/baselines.h"
#include "rom/eval/error_budget.h"
#include "rom/step/latent_stepper.h"

namespace nsf {

struct RomReport {
  std::string scene;
  double mu = 0;
  bool has_mu = false;
  std::string sweep_parameter;  // what μ is (the scene's sweep.parameter)
  size_t particles = 0, output_points = 0;
  int latent_dim = 0, frames = 0, rom_steps_per_frame = 0, fom_steps_per_frame = 0;
  double frame_dt = 0;         // simulated seconds per frame
  double gamma = 0;            // 3|P|/r
  double train_seconds = 0;    // the model's training wall time (0: not recorded)
  std::string model_checksum;  // the model file's stored CRC-32 ("" for an older file)
  size_t samples = 0, samples_end = 0;
  double mean_N = 0, mean_K = 0;
  double energy_kept = 1;        // LatentStepper::inversion_energy_kept
  double latent_prior = 0;       // ε of the inversion's latent prior (m); 0: none
  std::string sampling;          // how S was chosen: random, cluster, qdeim
  double sample_condition = -1;  // with qdeim: the conditioning of g's tangents on S
  // Where ε came from: "command line", "scene" (its rom section, or none there) or "model" (the
  // model's calibration, `nsf calibrate`).
  std::string latent_prior_source;
  // The ROM step over the scene's Δt asked for (rom_steps_per_frame rounds it); asked "at the CFL
  // bound" (RomOptions::kDtRatioAtCfl), the one taken.
  double dt_ratio = 1;
  // Where it came from: "command line", "scene" (its rom section), "model" (`nsf calibrate
  // --dt-ratios`) or "default" (1).
  std::string dt_ratio_source;
  // The scene's settings read ("family" or "unseen") and what of the scene lies outside the
  // model's training family (RomSetup).
  std::string profile = "family";
  std::vector<std::string> outside_family;
  // LatentStepper::training_distance over frames 1…N; −1 when the model has no training latents.
  double training_distance_mean = 0, training_distance_max = 0;
  // The inversion's rms residual ‖g − x‖ on S after each frame's last step (RomDiagnostics::
  // last_residual), over frames 1…N, in units of the ROM grid's Δx: how far the latent space falls
  // short of the motion the MPM step gave the samples. Computed online, without a truth.
  double residual_cells_mean = 0, residual_cells_max = 0;
  int threads = 0;               // in use, for both engines alike
  std::string cpu;               // the processor they ran on (core/cpu_model.h)
  size_t quadrature_points = 0;  // particles that can join N: |P| unless the quadrature is thinned
  int quadrature_per_cell = 0;   // the run's thinned quadrature (0: every particle)
  double grid_factor = 1;        // the ROM grid's Δx over the scene's (RomOptions::grid_factor)
  long refreshes = 0;
  double delta = -1;  // eq. (11) against the ground truth; < 0 when there is none
  std::vector<double> delta_per_frame;
  // Relative errors of the run's τ and C against the ground truth's, √(Σ‖·−·*‖²/Σ‖·*‖²) over
  // all particles and frames 1…N; < 0 without a truth (or when the truth's field is zero).
  double stress_error = -1, affine_error = -1;
  std::string field_sources;  // where τ and C come from (h and l, or what replaces them)
  std::optional<ErrorBudgetResult> budget;  // with RomEvalOptions::budget
  Baselines baselines;                      // those RomEvalOptions asked for; the rest < 0
  double rom_seconds = 0;                   // the latent steps only
  double rom_setup_seconds = 0, rom_output_seconds = 0;
  RomTimes rom_times;
  double fom_seconds = -1;  // the full-order steps only; < 0 when not run
  double rom_peak_mib = 0, fom_peak_mib = -1, baseline_mib = 0;
  bool peak_reset = false;  // the kernel restarted the peak between the phases
  std::vector<std::string> warnings;
  // Steps the step guard redid (RomEvalOptions::guard), and how the last one was redone ("" for
  // none); guarded: the run went through the guard.
  bool guarded = false;
  long recoveries = 0;
  std::string last_recovery;
  // Where a collider first left the model's training box (rom/step/step_guard.h); "" for never.
  std::string training_note;
  std::string truth_file, rom_file;
  double speedup() const { return fom_seconds > 0 ? fom_seconds / rom_seconds : 0.0; }
  // The coarse engine's speed-up against full order; < 0 when either was not run.
  double coarse_speedup() const {
    return fom_seconds > 0 && baselines.coarse_seconds > 0 ? fom_seconds / baselines.coarse_seconds
                                                           : -1.0;
  }
};

// A run whose latent stayed this many training spreads or more from the training runs' latents,
// on average over its frames, gets a warning: h answered far from anything it was trained on,
// and such runs were the ones a draw of its training decided (docs/ROM.md, "Latent prior").
// Runs that went well stayed under 1 spread; the failing ones went 30 to 90.
constexpr double kLatentDriftWarning = 5.0;

// The warning for a run whose latent went `mean_spreads` from the training latents on average
// with the latent prior ε = `latent_prior` (m, 0: none), or "" below kLatentDriftWarning.
std::string latent_drift_warning(double mean_spreads, double latent_prior);

// The summary printed by `nsf rom` and `nsf demo`.
std::string format_rom_report(const RomReport& report);

}  // namespace nsf
