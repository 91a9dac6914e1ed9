#pragma once
// The sweep's manifest.json (docs/DATASETS.md): which run files a dataset holds, with each
// file's μ and split, so training reads a directory without opening every HDF5 file first.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "data/sweep_spec.h"

namespace nsf {

nlohmann::json make_manifest(const std::string& scene_name, const std::string& scene_file,
                             const SweepSpec& spec, const std::vector<std::string>& overrides,
                             const std::vector<SweepRun>& complete_runs);

// Writes <path>.tmp and renames it over <path>: a reader never sees half a manifest.
void write_json_atomically(const std::string& path, const nlohmann::json& j);

}  // namespace nsf
