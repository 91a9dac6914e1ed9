#pragma once
// What an interrupted or partial sweep left out of a dataset directory (docs/DATASETS.md): the
// runs its plan names but the directory lacks, and the temp files of runs killed mid-write.
// `nsf train` refuses such a dataset unless told (--allow-incomplete): it trained on 4 of 12
// runs, without test runs, without a word.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace nsf {

// Runs a sweep plans per split; -1 where unknown.
struct PlannedRuns {
  long train = -1, test = -1;
};

// From a manifest's "planned" object, or from a scene's "sweep" section ("train", "test").
PlannedRuns planned_in_manifest(const nlohmann::json& manifest);
PlannedRuns planned_in_scene(const std::string& scene_json);

// The sweep's file names ("train_3.h5") the plan has and `listed` (file names) lacks.
std::vector<std::string> unlisted_runs(const PlannedRuns& plan,
                                       const std::vector<std::string>& listed);

// "<split>_<k>.h5.tmp" files in `dir`: runs a killed sweep was writing.
std::vector<std::string> interrupted_runs(const std::filesystem::path& dir);

}  // namespace nsf
