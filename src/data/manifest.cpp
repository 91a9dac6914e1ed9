#include "data/manifest.h"

#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "core/temp_files.h"

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
  const std::string tmp = path + ".tmp";
  const TempFileRegistration registration(tmp);  // a fatal signal deletes it
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) fail("cannot write '", tmp, "'");
    out << j.dump(2) << "\n";
    out.close();
    if (!out) fail("cannot write '", tmp, "' (disk full?)");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) fail("cannot rename '", tmp, "' to '", path, "': ", ec.message());
}

}  // namespace nsf
