#pragma once
// A scene file as the commands read it. The engine's loader (mpm/scene/scene.h) checks the
// top-level keys and the sections it reads; the others are parsed here, each once and by its
// owner: "sweep" and "generalize" by src/data, "rom" by src/rom, "train" by src/nn (its
// "calibrate" by src/rom). Every command
// that loads a scene goes through this, so a misspelt key anywhere in a scene stops it with the key
// named.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "data/perturbation_spec.h"
#include "data/sweep_spec.h"
#include "mpm/scene/scene.h"
#include "nn/train_section.h"
#include "rom/calibration/calibration_recipe.h"
#include "rom/setup/rom_section.h"

namespace nsf {

// The sections of a scene that the engine does not read, as their owners parse them.
struct SceneSections {
  std::optional<SweepSpec> sweep;            // none: the scene has no "sweep"
  RomSection rom;                            // the defaults when the scene has no "rom"
  std::optional<TrainSection> train;         // none: the scene has no "train"
  std::vector<CalibrationRecipe> calibrate;  // its "calibrate" (none: none)
  // The unseen interactions `nsf generalize` draws from; none: the scene has no "generalize".
  std::optional<GeneralizeSpec> generalize;
};

// Parses those sections of `scene` (anything but a JSON object has none: the engine's loader
// rejects it). Throws nsf::Error naming the key at fault.
SceneSections parse_scene_sections(const nlohmann::json& scene);

struct SceneFile {
  std::string path;
  std::string dir;      // the file's directory: relative mesh paths resolve against it
  nlohmann::json json;  // as read, overrides applied
  std::vector<std::string> overrides;  // as given (`--set`), in order
  SceneSections sections;
};

// read_scene_json, then parse_scene_sections; errors name the file.
SceneFile read_scene_file(const std::string& path, const std::vector<std::string>& overrides = {});

// build_scene of `json` (the file's own, or one made from it such as the file at a sweep's μ) with
// the file's directory; errors name the file.
Scene build_scene_file(const SceneFile& file, const nlohmann::json& json);
inline Scene build_scene_file(const SceneFile& file) {
  return build_scene_file(file, file.json);
}

}  // namespace nsf
