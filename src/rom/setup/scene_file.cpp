#include "rom/setup/scene_file.h"

#include <filesystem>

#include "core/error.h"

namespace nsf {

SceneSections parse_scene_sections(const nlohmann::json& scene) {
  SceneSections s;
  if (!scene.is_object()) return s;
  if (scene.contains("sweep")) s.sweep = parse_sweep(scene.at("sweep"), scene);
  if (scene.contains("rom")) s.rom = parse_rom_section(scene.at("rom"));
  if (scene.contains("train")) {
    s.train = parse_train_section(scene.at("train"));
    s.calibrate = parse_calibration_recipes(scene.at("train"));
  }
  if (scene.contains("generalize") && !scene.at("generalize").is_null())  // null: none
    s.generalize = parse_generalize(scene.at("generalize"), scene, s.sweep ? &*s.sweep : nullptr);
  return s;
}

SceneFile read_scene_file(const std::string& path, const std::vector<std::string>& overrides) {
  SceneFile f;
  f.path = path;
  f.dir = std::filesystem::path(path).parent_path().string();
  f.json = read_scene_json(path, overrides);
  f.overrides = overrides;
  try {
    f.sections = parse_scene_sections(f.json);
  } catch (const Error& e) {
    fail(path, ": ", e.what());
  }
  return f;
}

Scene build_scene_file(const SceneFile& file, const nlohmann::json& json) {
  try {
    return build_scene(json, file.dir);
  } catch (const Error& e) {
    fail(file.path, ": ", e.what());
  }
}

}  // namespace nsf
