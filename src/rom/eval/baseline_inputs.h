#pragma once
// The baselines' inputs (rom/eval/baselines.h), read before any long run so that a bad one stops
// an evaluation at once: the training runs for look-up and interpolation, and the coarse scene
// at μ, built once.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "rom/eval/baselines.h"
#include "rom/eval/rom_evaluation.h"

namespace nsf {

struct BaselineInputs {
  std::vector<TrainingRun> runs;  // look-up and interpolation; empty: not asked for
  std::optional<SceneFile> coarse;
  nlohmann::json coarse_json;  // at μ
  std::string label;           // what the coarse engine runs, for the report
  std::string coarse_skipped;  // why the coarse engine is not measured (coarse_optional)
  std::string coarse_note;     // the coarser factor it fell back to, and why
};

// Those `o` asks for, for the run `setup` describes. Throws nsf::Error naming the dataset or
// scene at fault (a coarse scene that cannot be built only sets coarse_skipped when
// o.coarse_optional, after this scene coarsened has stepped down to 1.1x).
BaselineInputs read_baseline_inputs(const RomEvalOptions& o, const RomSetup& setup);

}  // namespace nsf
