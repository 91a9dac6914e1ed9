#include "data/manifest.h"

#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "io/atomic_file.h"

namespace nsf {

nlohmann::json make_manifest(const std::string& scene_name, const std::string& scene_file,
                             const SweepSpec& spec, const std::vector<std::string>& overrides,
                             const std::vector<SweepRun>& complete_runs) {
  nlohmann::json runs = nlohmann::json::array();
  for (const SweepRun& r : complete_runs) {
    nlohmann::json e = {{"file", r.file()}, {"split", r.split}, {"index", r.index}, {"mu", r.mu}};
    if (!spec.vary.empty() || !spec.paths.empty()) e["values"] = sweep_values(spec, r);
    if (!spec.paths.empty()) e["path_seed"] = r.path_seed;
    runs.push_back(std::move(e));
  }
  nlohmann::json axes = nlohmann::json::array();
  for (const ParameterAxis& a : spec.vary)
    axes.push_back({{"name", a.name}, {"range", {a.lo, a.hi}}});
  nlohmann::json paths = nlohmann::json::array();
  for (const ColliderPath& p : spec.paths)
    paths.push_back({{"name", p.name}, {"collider", p.collider}, {"max_speed", p.max_speed}});
  const char* design = spec.design == SweepDesign::grid  ? "grid"
                       : spec.design == SweepDesign::lhs ? "lhs"
                                                         : "sobol";
  return {{"format", "nsf-sweep"},
          {"format_version", 1},
          {"scene", scene_name},
          {"scene_file", scene_file},
          {"overrides", overrides},
          {"sweep_parameter", spec.parameter},
          {"range", {spec.lo, spec.hi}},
          {"planned", {{"train", spec.train}, {"test", spec.test}}},
          {"design", design},
          {"seed", spec.seed},
          {"vary", axes},
          {"paths", paths},
          {"runs", runs}};
}

void write_json_atomically(const std::string& path, const nlohmann::json& j) {
  write_file_atomic(path, j.dump(2) + "\n");
}

}  // namespace nsf
