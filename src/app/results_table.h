#pragma once
// docs/RESULTS.md: the paper's Table 1 on nsf. Each `nsf report` run stores its measurements
// as one JSON file per scene and μ (so scenes can be run at different times) and the page is
// rebuilt from all of them, next to the paper's own figures.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "rom/eval/rom_evaluation.h"

namespace nsf::app {

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

// The markdown page for all rows (sorted by scene), naming `command` as its source, with the
// benchmark of unseen interactions (`nsf generalize`'s summaries, rom/eval/generalize.h) where
// given.
std::string results_markdown(const std::vector<nlohmann::json>& rows, const std::string& command,
                             const std::vector<nlohmann::json>& generalize = {});

// DOCS/RESULTS.md rebuilt from every row stored in DOCS/results/*.json and every summary in
// DOCS/results/generalize/*.json (written to a temporary name, then renamed); returns the number
// of rows. `nsf report` and `nsf demo --docs` call it.
size_t write_results_page(const std::string& docs);

}  // namespace nsf::app
