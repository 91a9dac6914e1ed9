#pragma once
// Choosing a model's latent prior ε by measurement (docs/ROM.md, "Latent prior"): the ROM of the
// scene's rom section, at a few training runs' μ and against those runs, once per ε of a grid;
// the ε with the lowest mean δ wins, a run that diverges ruling its ε out. Training runs, not
// held-out ones: they are what a user has before any test. `nsf calibrate` and `nsf train`.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace nsf {

struct CalibrationOptions {
  std::string model_path, data_dir;
  std::string scene_path;  // empty: the dataset manifest's scene_file
  std::vector<double> grid = {0, 1e-4, 3e-4, 1e-3, 2e-3};  // ε tried (m); 0: no prior
  int runs = 4;     // training runs, spread over the sweep's interior
  int threads = 0;  // as `nsf rom -j`; 0: all cores
  bool quiet = false;
};

struct CalibrationResult {
  std::vector<double> grid;
  std::vector<std::string> runs;  // the training runs' files
  std::vector<double> mu;
  // δ per ε and run: +inf where the latent dynamics diverged, NaN where the run was skipped
  // (its ε had diverged on an earlier run, or was stopped).
  std::vector<std::vector<double>> delta;
  std::vector<double> mean;  // per ε; +inf where a run diverged; a lower bound where stopped
  // Per ε: stopped after some runs because its runs so far already put its mean above the lowest
  // complete mean before it (it could not win; the choice is the whole grid's).
  std::vector<bool> stopped;
  double chosen = 0;  // the ε with the lowest mean (0 where every ε diverged)
  bool all_diverged = false;
  double seconds = 0;

  nlohmann::json to_json() const;
  std::string table() const;    // what `nsf calibrate` prints
  std::string summary() const;  // one line: the choice and its mean δ (a poor one shows here)
};

// The scene file a dataset was swept from (its manifest's scene_file), or "" where the manifest
// names none or the file is not there.
std::string dataset_scene_file(const std::string& data_dir);

// The latent prior a scene file's rom section sets, which `nsf rom` takes ahead of a model's
// calibration (none where it sets none).
std::optional<double> scene_latent_prior(const std::string& scene_path);

// Runs the ROM grid × runs times. Throws nsf::Error for a missing scene or dataset, a model of
// another scene, or any failure of a run other than divergence.
CalibrationResult calibrate_latent_prior(const CalibrationOptions& options);

// What `nsf train`, `nsf demo` and `nsf report` do after training a model: calibrate it (and
// store the result) where it is a basis model (an MLP model's ROM is ~50x slower: `nsf calibrate`
// it by hand), the dataset has μ and its scene file is here and sets no latent_prior itself; prints
// the table unless quiet, or a note saying why it was skipped (also where the ROM runs fail: the
// trained model stands). Returns whether it calibrated.
bool calibrate_trained_model(const std::string& model_path, const std::string& data_dir,
                             int threads, bool quiet);

// Stores the chosen ε and the table (to_json) in the model file, atomically; `nsf rom` then uses
// that ε where neither its command line nor the scene's rom section gives one.
void store_calibration(const std::string& model_path, const CalibrationResult& result);

}  // namespace nsf
