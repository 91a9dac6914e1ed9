#pragma once
// A scene's calibration recipes, "calibrate" in its "train" section (docs/SCENES.md, "Training
// recipe"): how `nsf calibrate` measures a model of the scene where its command line does not
// say, and how `nsf train`, `nsf report` and `nsf demo` calibrate what they train
// (rom/calibration/latent_prior_calibration.h). The rest of the section is the trainer's
// (nn/train_section.h); the scene file hands each part to its owner (rom/setup/scene_file.h).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace nsf {

// The ε tried, the ROM steps tried (none: the step is not chosen) and scene values set for those
// runs (`--set`). A scene may give several (a list), one for each kind of run a model keeps a
// calibration of: the decoded stress's and the tracked state's
// (`"set": ["rom.fields.stress=tracked", ...]`).
// A recipe with "unseen": true calibrates the scene's rom.unseen profile on "draws" perturbed
// cases (CalibrationOptions::unseen).
struct CalibrationRecipe {
  std::vector<double> grid, dt_ratios;
  std::vector<std::string> set;
  bool unseen = false;
  int draws = 0;  // 0: not given
};

// The recipes of a scene's "train" section `train` (at `path`): its "calibrate", one recipe or a
// non-empty list of them, made in turn; none where it has no "calibrate". Throws nsf::Error naming
// the key at fault.
std::vector<CalibrationRecipe> parse_calibration_recipes(const nlohmann::json& train,
                                                         const std::string& path = "train");

}  // namespace nsf
