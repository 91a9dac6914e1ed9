#pragma once
// docs/RESULTS.md: the paper's Table 1 on nsf. Each `nsf report` run stores its measurements
// as one JSON file per scene and μ (rom/eval/result_row.h), so that scenes can be run at
// different times, and the page is rebuilt from all of them, next to the paper's own figures.
// The page's prose is a template (rom/eval/templates/results_page.md); the tables are made here.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace nsf {

// The markdown page for all rows (sorted by scene), naming `command` as its source, with the
// benchmark of unseen interactions (`nsf generalize`'s summaries, rom/eval/generalize.h) where
// given.
std::string results_markdown(const std::vector<nlohmann::json>& rows, const std::string& command,
                             const std::vector<nlohmann::json>& generalize = {});

// DOCS/RESULTS.md rebuilt from every row stored in DOCS/results/*.json and every summary in
// DOCS/results/generalize/*.json (written to a temporary name, then renamed); returns the number
// of rows. `nsf report` and `nsf demo --docs` call it.
size_t write_results_page(const std::string& docs);

// The page's template, embedded at build time (generated from templates/results_page.md).
const char* results_page_template();

}  // namespace nsf
