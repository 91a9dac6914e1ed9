#pragma once
// Choosing a model's latent prior ε by measurement (docs/ROM.md, "Latent prior"): the ROM of the
// scene's rom section, at a few training runs' μ and against those runs, once per ε of a grid;
// the ε with the lowest mean δ wins, a run that diverges ruling its ε out. Training runs, not
// held-out ones: they are what a user has before any test. `nsf calibrate` and `nsf train`.
// Optionally also the ROM's time step (`--dt-ratios`): at the chosen ε, the largest ratio of the
// ROM step to the scene's Δt whose mean δ stays within a tolerance of the best ratio's.
// With `--unseen`, the scene's rom.unseen profile instead, on perturbed cases drawn from its
// "generalize" section (never the benchmark's draws) against their own full-order runs: what a
// run outside the training family takes, chosen on runs outside it.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "nn/config.h"

namespace nsf {

struct CalibrationOptions {
  std::string model_path, data_dir;
  std::string scene_path;  // empty: the dataset manifest's scene_file
  // Scene values set on top of the sweep's own (`--set rom.quadrature=1`): the ROM a user runs.
  std::vector<std::string> overrides;
  std::vector<double> grid = {0, 1e-4, 3e-4, 1e-3, 2e-3};  // ε tried (m); 0: no prior
  // ROM steps over the scene's Δt to try, ascending; the first is the reference, at which ε is
  // chosen. Empty: the step is not calibrated (ε is chosen at the step nsf rom would take).
  std::vector<double> dt_ratios;
  double dt_tolerance = 1.25;  // a ratio qualifies where its mean δ ≤ this × the best's,
  double dt_budget = 0;        // or ≤ this (a δ, e.g. 0.01; 0: none)
  int runs = 4;                // training runs, spread over the sweep's interior
  // Calibrate the scene's rom.unseen profile instead (`--unseen`), on perturbed cases, never on
  // training runs: `draws` draws of the scene's "generalize" section from `seed` (none: its
  // calibration_seed; never the benchmark's seed), each run at full order once as its truth,
  // the ROM on the unseen profile. Stored as the model's unseen calibration, which a run on that
  // profile takes where the profile sets no latent_prior (dt_ratio).
  bool unseen = false;
  int draws = 4;
  std::optional<uint64_t> seed;
  int threads = 0;  // as `nsf rom -j`; 0: all cores
  bool quiet = false;
};

// The step ratios tried at the chosen ε, on the same runs.
struct StepCalibration {
  std::vector<double> ratios;
  std::vector<int> steps_per_frame;  // the ROM steps a frame takes at each (rounded)
  // δ per ratio and run: +inf where the dynamics diverged or the ROM refused the step (a tracked
  // state's explicit stress past the CFL bound), NaN where skipped (as CalibrationResult::delta).
  std::vector<std::vector<double>> delta;
  std::vector<double> mean;  // per ratio; +inf where a run failed; a lower bound where stopped
  // Stopped after some runs because those already put its mean over the tolerance.
  std::vector<bool> stopped;
  std::vector<double> rom_ms_per_frame;  // the latent steps, mean over the runs measured
  double tolerance = 0, budget = 0;
  double limit = 0;    // the mean δ a ratio may reach: max(tolerance × the best's, budget)
  double chosen = -1;  // the largest ratio within the limit; < 0 where the first one failed
};

// The ratio with the lowest complete mean δ (the first where none is lower).
size_t best_step(const StepCalibration& s);
// The mean δ a ratio may reach: max(tolerance × the best's, budget).
double step_limit(const StepCalibration& s);
// The largest ratio within step_limit; -1 where the first failed (nothing to hold the others to).
double chosen_step(const StepCalibration& s);

struct CalibrationResult {
  std::vector<double> grid;
  std::vector<std::string> runs;  // the training runs' files, or the draws (unseen)
  std::vector<double> mu;         // NaN for a draw of a scene without a sweep
  // δ per ε and run: +inf where the latent dynamics diverged, NaN where the run was skipped
  // (its ε had diverged on an earlier run, or was stopped).
  std::vector<std::vector<double>> delta;
  std::vector<double> mean;  // per ε; +inf where a run diverged; a lower bound where stopped
  // Per ε: stopped after some runs because its runs so far already put its mean above the lowest
  // complete mean before it (it could not win; the choice is the whole grid's).
  std::vector<bool> stopped;
  double chosen = 0;  // the ε with the lowest mean (0 where every ε diverged)
  bool all_diverged = false;
  std::optional<StepCalibration> step;  // with CalibrationOptions::dt_ratios
  // The runs carried the tracked state (their stress "tracked"): the model keeps it apart.
  bool tracked = false;
  bool unseen = false;  // measured on perturbed cases (CalibrationOptions::unseen)
  uint64_t seed = 0;    // of their draws
  double seconds = 0;

  nlohmann::json to_json() const;
  std::string table() const;    // what `nsf calibrate` prints
  std::string summary() const;  // one line: the choice and its mean δ (a poor one shows here)
};

// The scene file a dataset was swept from (its manifest's scene_file), or "" where the manifest
// names none or the file is not there.
std::string dataset_scene_file(const std::string& data_dir);

// How many calibration recipes the scene gives (its train section's "calibrate": 0, 1 or a list).
size_t calibration_recipes(const std::string& scene_path);

// The scene's calibration recipe `index` (from 0) in place of what `o` was not given: the ε grid,
// the ROM steps and the `--set` values. Prints what it took unless quiet. Throws nsf::Error for an
// index the scene does not have (where it has any).
struct CalibrationGiven {
  bool grid = false, dt_ratios = false, set = false, unseen = false, draws = false;
};
void apply_calibration_recipe(CalibrationOptions& o, const CalibrationGiven& given,
                              size_t index = 0);

// What a scene file's rom section (with the calibration's --set values and its dataset's) gives a
// model of decoder family `family`, as `nsf rom` reads it: whether the runs carry the tracked
// state, and the latent prior and step it sets for them, which `nsf rom` takes ahead of the
// model's calibration (none where it sets none).
struct SceneRomSettings {
  bool tracked = false;
  std::optional<double> latent_prior, dt_ratio;
};
SceneRomSettings scene_rom_settings(const CalibrationOptions& o, DecoderFamily family);

// Runs the ROM grid × runs times. Throws nsf::Error for a missing scene or dataset, a model of
// another scene, or any failure of a run other than divergence.
CalibrationResult calibrate_latent_prior(const CalibrationOptions& options);

// What `nsf train`, `nsf demo` and `nsf report` do after training a model: calibrate it (and
// store the result) where it is a basis model (an MLP model's ROM is ~50x slower: `nsf calibrate`
// it by hand), the dataset has μ and its scene file is here, once per recipe of the scene (once
// where it has none) whose runs the scene gives no latent_prior; prints the table unless quiet,
// or a note saying why it was skipped (also where the ROM runs fail: the trained model stands).
// Returns whether it calibrated.
bool calibrate_trained_model(const std::string& model_path, const std::string& data_dir,
                             int threads, bool quiet);

// Stores the chosen ε (and the step ratio, where calibrated) and the table (to_json) in the
// model file, atomically, as the calibration of the kind of run it measured (result.tracked);
// `nsf rom` then uses them where neither its command line nor the scene's rom section gives its
// own.
void store_calibration(const std::string& model_path, const CalibrationResult& result);

}  // namespace nsf
