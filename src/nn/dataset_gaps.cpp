#include "nn/dataset_gaps.h"

#include <algorithm>
#include <regex>

namespace nsf {

namespace fs = std::filesystem;

namespace {

PlannedRuns counts(const nlohmann::json& j) {
  PlannedRuns p;
  if (!j.is_object()) return p;
  if (j.contains("train") && j["train"].is_number_integer()) p.train = j["train"].get<long>();
  if (j.contains("test") && j["test"].is_number_integer()) p.test = j["test"].get<long>();
  return p;
}

}  // namespace

PlannedRuns planned_in_manifest(const nlohmann::json& manifest) {
  return manifest.is_object() && manifest.contains("planned") ? counts(manifest["planned"])
                                                              : PlannedRuns{};
}

PlannedRuns planned_in_scene(const std::string& scene_json) {
  const nlohmann::json j = nlohmann::json::parse(scene_json, nullptr, false);
  return j.is_object() && j.contains("sweep") ? counts(j["sweep"]) : PlannedRuns{};
}

std::vector<std::string> unlisted_runs(const PlannedRuns& plan,
                                       const std::vector<std::string>& listed) {
  std::vector<std::string> names;
  for (const auto& [split, count] : {std::pair{"train", plan.train}, std::pair{"test", plan.test}})
    for (long k = 0; k < std::min(count, 100000L); ++k) {
      const std::string name = std::string(split) + "_" + std::to_string(k) + ".h5";
      const bool found = std::any_of(listed.begin(), listed.end(), [&](const std::string& l) {
        return fs::path(l).filename() == name;
      });
      if (!found) names.push_back(name);
    }
  return names;
}

std::vector<std::string> interrupted_runs(const fs::path& dir) {
  static const std::regex re("(train|test)_[0-9]+\\.h5\\.tmp");
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (std::regex_match(name, re)) names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace nsf
