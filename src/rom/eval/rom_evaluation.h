#pragma once
// A reduced-order run of a scene at a parameter μ against full order: the run written in the
// layout of `nsf simulate`, compared with the full-order engine on the same scene in the same
// process (wall time, peak memory) and with a ground truth (δ of eq. 11, τ and C), with the error
// budget and the simple baselines beside it. The library behind `nsf rom`, `nsf demo`,
// `nsf report`, `nsf calibrate` and `nsf generalize`.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "rom/eval/rom_report.h"
#include "rom/setup/rom_setup.h"

namespace nsf {

struct RomEvalOptions {
  std::string model_path, scene_path;
  std::vector<std::string> overrides;  // --set, applied before μ
  std::optional<double> mu;            // applied through the scene's "sweep" templates
  std::optional<int> samples;          // |S| at t = 0; default: the scene's "rom" section
  std::optional<uint64_t> seed;        // of the sample choice; default: the scene's, else 1
  std::optional<double> dt_ratio;      // ROM step over Δt; default: the scene's, else rom's
  std::optional<double> latent_prior;  // ε (m); default: the scene's, else the model's, else 0
  std::optional<int> quadrature;       // points per cell; default: the scene's, else rom's (0)
  std::optional<int> gn_iterations;    // Gauss–Newton cap; default: the scene's, else rom's
  std::string profile = "auto";        // RomSettingChoices::profile
  // rom.fields names the sources the command line chose; each empty one takes the scene's.
  RomOptions rom;
  std::string out_path;    // ROM run file; empty: none
  std::string truth_path;  // existing ground truth; empty: the full-order run made here
  std::string fom_out;     // where the full-order run goes; empty: a temporary file
  bool full_order = true;  // run the full-order engine for timing and as the ground truth
  // Step as the runtime steps, through the step guard (rom/step/step_guard.h): a step that
  // diverges or passes the error indicator's limits is redone (RomReport::recoveries). Off: the
  // bare stepper, whose divergence ends the run (a redone step also costs a run its momentum,
  // docs/experiments/2026-11-30-app-b-weak-elements.md).
  bool guard = false;
  int upsample = 1;  // positions of k points per particle in the output file (Fig. 6)
  int gzip = 0;      // deflate level of both run files (0 = off; io/run_writer.h)
  int threads = 0;   // OpenMP and torch threads, for both engines alike; 0: all cores
  bool quiet = false;
  bool print_warnings = true;  // the setup's warnings on stderr too (the report keeps them)
  // Also measure the error budget on the truth's frames (rom/eval/error_budget.h; needs a truth).
  bool budget = false;
  // The simple baselines of rom/eval/baselines.h, against the same truth (needs one): look-up and
  // interpolation from this dataset's training runs; the coarse engine on coarse_scene (else
  // this scene), with `overrides` and μ, made coarse_factor times coarser where that is > 1.
  std::string baseline_data;
  // The case's values of the sweep's "vary" axes, by name: look-up and interpolation then search
  // the box of μ and the axes (`nsf generalize` sets them); empty: μ alone.
  std::map<std::string, double> axes;
  std::string coarse_scene;
  double coarse_factor = 0;
  // A coarse scene that cannot be built (a body inside the coarser wall band, say) leaves the
  // coarse engine unmeasured, with a warning in the report, instead of stopping the run
  // (`nsf report` and `nsf generalize`, which pick the coarse scene themselves; `nsf rom
  // --coarse` stops). This scene coarsened steps down by tenths of coarse_factor to 1.1 first,
  // with a warning naming the factor that ran.
  bool coarse_optional = false;
};

// Gauss–Newton iterations the budget's projection allows per frame: its warm start is a frame
// (many ROM steps) old, so it runs to convergence rather than the ROM's per-step cap.
constexpr int kBudgetIterations = 20;

RomReport evaluate_rom(const RomEvalOptions& options);

}  // namespace nsf
