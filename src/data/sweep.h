#pragma once
// `nsf sweep`: every training and test simulation of a scene's "sweep" section (docs/SCENES.md),
// written as <out>/<split>_<k>.h5 plus <out>/manifest.json (docs/DATASETS.md). Resumable: a run
// whose file is already complete for the same scene and μ is not redone.
#include <string>
#include <vector>

namespace nsf {

struct SweepOptions {
  std::string out_dir;
  std::vector<std::string> overrides;  // applied to the scene before the sweep's own
  std::string only;                    // "", "train" or "test"
  int jobs = 1;                        // simulations at once
  int threads = 1;                     // OpenMP threads per simulation
  bool quiet = false;                  // no progress line
};

struct SweepSummary {
  int planned = 0;  // runs selected (after --only)
  int ran = 0;      // simulated now
  int skipped = 0;  // already complete
  double seconds = 0;
};

SweepSummary run_sweep(const std::string& scene_path, const SweepOptions& options);

// True if `path` is a complete run file of this scene JSON (μ applied): it opens, holds
// frames + 1 frames and stores the same scene, up to the keys that do not change the simulation
// ("description", "camera", "rom"). Anything else (missing, truncated, another scene
// or μ, a foreign file) is false, and the run is redone.
bool is_complete_run(const std::string& path, const std::string& scene_json, int frames);

}  // namespace nsf
