#pragma once
// A reduced-order run's row, as `nsf report`, `nsf demo --docs` and `nsf rom --json` store it
// (docs/results/*.json, what scripts check), and the rule by which a rerun reproduces one
// (`nsf report --check`).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "rom/eval/rom_report.h"

namespace nsf {

// One row: the report's measurements plus what it was made of.
nlohmann::json result_json(const RomReport& r, const std::string& scene_file,
                           const std::string& model_file, const std::string& picture,
                           const std::string& label);

// What a rerun of a row must reproduce bit for bit: every key but the machine's (timings, memory,
// speed-ups, thread count: `…_seconds`, `…_mib`, `speedup`, `coarse_speedup`, `threads`), the
// picture's path and provenance (where a setting came from, the model file's checksum). One line
// per stored key that differs or that the rerun lacks ("delta: stored 0.00508, now 0.00509"); none
// when the row reproduces. Keys only the rerun has (recorded since the row was made) are not
// differences.
std::vector<std::string> row_differences(const nlohmann::json& stored, const nlohmann::json& fresh);

}  // namespace nsf
