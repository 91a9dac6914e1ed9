#pragma once
// `nsf sweep`: every training and test simulation of a scene's "sweep" section (docs/SCENES.md),
// written as <out>/<split>_<k>.h5 plus <out>/manifest.json (docs/DATASETS.md). Resumable: a run
// whose file is already complete for the same scene and μ is not redone.
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "data/sweep_spec.h"

namespace nsf {

// Several processes running one sweep together (`mpirun -np K nsf sweep`; app/sweep_ranks.h
// implements it over MPI, so that this layer knows no MPI). Runs are named by their index in
// plan_sweep's list.
class SweepTeam {
 public:
  virtual ~SweepTeam() = default;
  // Gets the runs not yet complete, as this process sees them; returns the ones this process
  // simulates. Across the team every pending run goes to exactly one process.
  virtual std::vector<int> share(const std::vector<int>& pending) = 0;
  // Gets the runs this process completed. Waits for every process, calls `write_manifest` with
  // all of theirs on exactly one process, and returns only when it has returned there.
  virtual void collect(
      const std::vector<int>& done,
      const std::function<void(const std::vector<int>& all_done)>& write_manifest) = 0;
};

struct SweepOptions {
  std::string out_dir;
  std::vector<std::string> overrides;  // applied to the scene before the sweep's own
  std::string only;                    // "", "train" or "test"
  int jobs = 1;                        // simulations at once
  int threads = 1;                     // OpenMP threads per simulation
  bool quiet = false;                  // no progress line
  int gzip = 0;                        // deflate level of the run files' frames (0 = off)
  SweepTeam* team = nullptr;           // none: this process runs everything
};

struct SweepSummary {
  int planned = 0;  // runs selected (after --only)
  int ran = 0;      // simulated now (by the whole team, on the process that wrote the manifest)
  int skipped = 0;  // already complete
  double seconds = 0;
};

// Reads the scene file (options.overrides applied), parses its "sweep" section and runs it.
SweepSummary run_sweep(const std::string& scene_path, const SweepOptions& options);

// The same for a scene its caller has read from `scene_path` (options.overrides already applied;
// the manifest records them) and whose "sweep" section it has parsed: `spec`, none when the scene
// has no such section (an error).
SweepSummary run_sweep(const nlohmann::json& scene, const std::optional<SweepSpec>& spec,
                       const std::string& scene_path, const SweepOptions& options);

// True if `path` is a complete run file of this scene JSON (μ applied): it opens, holds
// frames + 1 frames and stores the same scene, up to the keys that do not change the simulation
// ("description", "camera", "rom"). Anything else (missing, truncated, another scene
// or μ, a foreign file) is false, and the run is redone.
bool is_complete_run(const std::string& path, const std::string& scene_json, int frames);

}  // namespace nsf
