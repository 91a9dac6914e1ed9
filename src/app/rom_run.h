#pragma once
// `nsf rom`: a reduced-order run of a scene at a parameter μ, written in the layout of
// `nsf simulate`, compared with the full-order engine on the same scene in the same process
// (wall time, peak memory) and with a ground truth (δ of eq. 11). Shared by `nsf rom`,
// `nsf demo` and `nsf report`.
#include <optional>
#include <string>
#include <vector>

#include "app/baselines.h"
#include "rom/error_budget.h"
#include "rom/latent_stepper.h"

namespace nsf {

struct RomRunOptions {
  std::string model_path, scene_path;
  std::vector<std::string> overrides;  // --set, applied before μ
  std::optional<double> mu;            // applied through the scene's "sweep" templates
  std::optional<int> samples;          // |S| at t = 0; default: the scene's "rom" section
  std::optional<uint64_t> seed;        // of the sample choice; default: the scene's, else 1
  std::optional<double> dt_ratio;      // ROM step over Δt; default: the scene's, else rom's
  std::optional<double> latent_prior;  // ε (m); default: the scene's, else the model's, else 0
  std::optional<int> quadrature;       // points per cell; default: the scene's, else rom's (0)
  std::optional<int> gn_iterations;    // Gauss–Newton cap; default: the scene's, else rom's
  // rom.fields names the sources the command line chose; each empty one takes the scene's.
  RomOptions rom;
  std::string out_path;    // ROM run file; empty: none
  std::string truth_path;  // existing ground truth; empty: the full-order run made here
  std::string fom_out;     // where the full-order run goes; empty: a temporary file
  bool full_order = true;  // run the full-order engine for timing and as the ground truth
  int upsample = 1;        // positions of k points per particle in the output file (Fig. 6)
  int gzip = 0;            // deflate level of both run files (0 = off; io/run_writer.h)
  int threads = 0;         // OpenMP and torch threads, for both engines alike; 0: all cores
  bool quiet = false;
  // Also measure the error budget on the truth's frames (rom/error_budget.h; needs a truth).
  bool budget = false;
  // The simple baselines of app/baselines.h, against the same truth (needs one): look-up and
  // interpolation from this dataset's training runs; the coarse engine on coarse_scene (else
  // this scene), with `overrides` and μ, made coarse_factor times coarser where that is > 1.
  std::string baseline_data;
  std::string coarse_scene;
  double coarse_factor = 0;
  // A coarse scene that cannot be built (a body inside the coarser wall band, say) leaves the
  // coarse engine unmeasured, with a warning in the report, instead of stopping the run
  // (`nsf report`, which picks the coarse scene itself; `nsf rom --coarse` stops).
  bool coarse_optional = false;
};

// Gauss–Newton iterations the budget's projection allows per frame: its warm start is a frame
// (many ROM steps) old, so it runs to convergence rather than the ROM's per-step cap.
constexpr int kBudgetIterations = 20;

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
  double dt_ratio =
      1;  // the ROM step over the scene's Δt asked for (rom_steps_per_frame rounds it)
  // Where it came from: "command line", "scene" (its rom section), "model" (`nsf calibrate
  // --dt-ratios`) or "default" (1).
  std::string dt_ratio_source;
  // LatentStepper::training_distance over frames 1…N; −1 when the model has no training latents.
  double training_distance_mean = 0, training_distance_max = 0;
  // The inversion's rms residual ‖g − x‖ on S after each frame's last step (RomDiagnostics::
  // last_residual), over frames 1…N, in units of the scene's Δx: how far the latent space falls
  // short of the motion the MPM step gave the samples. Computed online, without a truth.
  double residual_cells_mean = 0, residual_cells_max = 0;
  int threads = 0;               // in use, for both engines alike
  std::string cpu;               // the processor they ran on (core/cpu_model.h)
  size_t quadrature_points = 0;  // particles that can join N: |P| unless the quadrature is thinned
  int quadrature_per_cell = 0;   // the run's thinned quadrature (0: every particle)
  long refreshes = 0;
  double delta = -1;  // eq. (11) against the ground truth; < 0 when there is none
  std::vector<double> delta_per_frame;
  // Relative errors of the run's τ and C against the ground truth's, √(Σ‖·−·*‖²/Σ‖·*‖²) over
  // all particles and frames 1…N; < 0 without a truth (or when the truth's field is zero).
  double stress_error = -1, affine_error = -1;
  std::string field_sources;  // where τ and C come from (h and l, or what replaces them)
  std::optional<ErrorBudgetResult> budget;  // with RomRunOptions::budget
  Baselines baselines;                      // those RomRunOptions asked for; the rest < 0
  double rom_seconds = 0;                   // the latent steps only
  double rom_setup_seconds = 0, rom_output_seconds = 0;
  RomTimes rom_times;
  double fom_seconds = -1;  // the full-order steps only; < 0 when not run
  double rom_peak_mib = 0, fom_peak_mib = -1, baseline_mib = 0;
  bool peak_reset = false;  // the kernel restarted the peak between the phases
  std::vector<std::string> warnings;
  std::string truth_file, rom_file;
  double speedup() const { return fom_seconds > 0 ? fom_seconds / rom_seconds : 0.0; }
  // The coarse engine's speed-up against full order; < 0 when either was not run.
  double coarse_speedup() const {
    return fom_seconds > 0 && baselines.coarse_seconds > 0 ? fom_seconds / baselines.coarse_seconds
                                                           : -1.0;
  }
};

RomReport run_rom(const RomRunOptions& options);

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
