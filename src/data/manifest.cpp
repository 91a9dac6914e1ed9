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
  for (const SweepRun& r : complete_runs)
    runs.push_back({{"file", r.file()}, {"split", r.split}, {"index", r.index}, {"mu", r.mu}});
  return {{"format", "nsf-sweep"},
          {"format_version", 1},
          {"scene", scene_name},
          {"scene_file", scene_file},
          {"overrides", overrides},
          {"sweep_parameter", spec.parameter},
          {"range", {spec.lo, spec.hi}},
          {"planned", {{"train", spec.train}, {"test", spec.test}}},
          {"runs", runs}};
}

void write_json_atomically(const std::string& path, const nlohmann::json& j) {
  write_file_atomic(path, j.dump(2) + "\n");
}

}  // namespace nsf
