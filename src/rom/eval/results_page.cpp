#include "rom/eval/results_page.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "core/error.h"
#include "io/atomic_file.h"
#include "rom/eval/generalize.h"

namespace nsf {

namespace {

// What the paper reports per scene (Table 1 and §6): |P|, r, δ, and where given the samples,
// speed-up and memory (full order / ROM).
struct PaperFigures {
  const char* particles;
  const char* delta;
  const char* samples;
  const char* speedup;
  const char* memory;
};

const std::map<std::string, PaperFigures>& paper_figures() {
  static const std::map<std::string, PaperFigures> m = {
      {"bread", {"40,000", "1.2%", "—", "—", "—"}},
      {"cake", {"200,000", "1.3%", "700 → 400", "10.23×", "1.61 G / 0.79 G"}},
      {"sand", {"71,363", "0.4%", "150 (30 for the speed-up)", "5.05×", "0.91 G / 0.65 G"}},
      {"metal", {"49,978", "0.2–0.5%", "—", "—", "—"}},
      {"toothpaste", {"21,811", "0.6–1.8%", "15–50", "—", "—"}},
      {"jelly", {"10,000", "0.2% (CROM 16.6%)", "—", "—", "—"}},
      {"squishy_ball", {"97,857", "0.2%", "—", "—", "—"}},
  };
  return m;
}

std::string base_scene(const std::string& name) {
  for (const auto& [k, v] : paper_figures())
    if (name.rfind(k, 0) == 0) return k;
  return name;
}

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

// A stored fraction as a percentage; — when absent (older rows) or not measured (< 0).
std::string percent_or_dash(const nlohmann::json& j, const char* key, const char* format) {
  if (!j.contains(key) || j[key].get<double>() < 0) return "—";
  return fmt(format, 100 * j[key].get<double>());
}

// The row's name: its scene and label. A row whose quadrature was thinned by the scene's rom
// section, not by `nsf report --quadrature` (whose label names it), says so.
std::string row_name(const nlohmann::json& j) {
  std::string label = j["label"].get<std::string>();
  const size_t points = j.value("quadrature_points", size_t(0));  // 0: not recorded
  const bool thinned = points > 0 && points < j["particles"].get<size_t>();
  if (thinned && label.find("quadrature") == std::string::npos) {
    const int k = j.value("quadrature_per_cell", 0);
    const std::string q = k > 0 ? "quadrature " + std::to_string(k) + "/cell, the scene's"
                                : "thinned quadrature, the scene's";
    label = label.empty() ? q : label + ", " + q;
  }
  return j["scene"].get<std::string>() + (label.empty() ? "" : " (" + label + ")");
}

// Which decoder family the row's model holds, as its field sources name it ("x from g's basis").
// Rows stored before the sources were recorded predate the bases (2026-11-26): MLP fields.
std::string decoders(const nlohmann::json& j) {
  if (!j.contains("field_sources")) return "MLP";
  return j["field_sources"].get<std::string>().find("basis") != std::string::npos ? "bases" : "MLP";
}

// Table 1: each row's setup, δ, speed-up and memory beside the paper's figures.
std::string setup_rows(const std::vector<nlohmann::json>& rows) {
  std::ostringstream s;
  for (const auto& j : rows) {
    const std::string base = base_scene(j["scene"]);
    const auto it = paper_figures().find(base);
    std::string paper = "—";
    if (it != paper_figures().end()) {
      const PaperFigures& p = it->second;
      paper = std::string(p.particles) + ", " + p.delta + ", " + p.samples + ", " + p.speedup +
              ", " + p.memory;
    }
    std::string samples = std::to_string(j["samples"].get<size_t>());
    if (j["samples_end"] != j["samples"])
      samples += " → " + std::to_string(j["samples_end"].get<size_t>());
    const double frames = j["frames"].get<double>();
    const std::string prior = j.contains("latent_prior") && j["latent_prior"].get<double>() > 0
                                  ? fmt("%g mm", 1e3 * j["latent_prior"].get<double>())
                                  : "—";
    s << "| " << row_name(j) << " | " << fmt("%g", j["mu"]) << " | " << j["particles"].get<size_t>()
      << " | " << j["r"].get<int>() << " | " << decoders(j) << " | " << fmt("%.3g", j["gamma"])
      << " | " << samples << " | " << fmt("%.0f", j["mean_N"]) << " | " << prior << " | "
      << percent_or_dash(j, "delta", "%.2f%%") << " | "
      << percent_or_dash(j, "stress_error", "%.0f%%") << " | " << fmt("%.2f×", j["speedup"])
      << " | " << fmt("%.1f", 1e3 * j["rom_seconds"].get<double>() / frames) << " | "
      << fmt("%.1f", 1e3 * j["fom_seconds"].get<double>() / frames) << " | "
      << fmt("%.0f", j["fom_peak_mib"]) << " / " << fmt("%.0f", j["rom_peak_mib"]) << " | " << paper
      << " |\n";
  }
  return s.str();
}

// Each row beside what a user could run instead.
std::string baseline_rows(const std::vector<nlohmann::json>& rows) {
  std::ostringstream s;
  for (const auto& j : rows) {
    std::string lookup = percent_or_dash(j, "lookup_delta", "%.2f%%");
    if (j.contains("lookup_mu")) lookup += fmt(" (%g)", j["lookup_mu"]);
    std::string interp = percent_or_dash(j, "interp_delta", "%.2f%%");
    if (j.value("interp_extrapolated", false)) interp += " (extrapolated)";
    s << "| " << row_name(j) << " | " << fmt("%g", j["mu"]) << " | "
      << percent_or_dash(j, "delta", "%.2f%%") << " | " << fmt("%.2f×", j["speedup"]) << " | "
      << lookup << " | " << interp << " | " << percent_or_dash(j, "coarse_delta", "%.2f%%") << " | "
      << (j.contains("coarse_speedup") && j["coarse_speedup"].get<double>() > 0
              ? fmt("%.2f×", j["coarse_speedup"])
              : std::string("—"))
      << " | "
      << (j.contains("coarse_scene")
              ? j["coarse_scene"].get<std::string>() + fmt(", %g particles", j["coarse_particles"])
              : std::string("—"))
      << " |\n";
  }
  return s.str();
}

// Where each row's reduced-order time went.
std::string time_rows(const std::vector<nlohmann::json>& rows) {
  std::ostringstream s;
  for (const auto& j : rows) {
    const double t = j["rom_seconds"].get<double>();
    auto pct = [&](const char* k) {
      return fmt("%.2f s", j[k].get<double>()) + fmt(" (%.0f%%)", 100 * j[k].get<double>() / t);
    };
    s << "| " << row_name(j) << " | " << pct("inference_seconds") << " | " << pct("mpm_seconds")
      << " | " << pct("inversion_seconds") << " | " << pct("refresh_seconds") << " | "
      << j["rom_steps_per_frame"].get<int>() << " | " << j["fom_steps_per_frame"].get<int>()
      << " | "
      << (j.contains("threads") ? std::to_string(j["threads"].get<int>()) : std::string("—"))
      << " | "
      << (j.contains("train_seconds") ? fmt("%.1f min", j["train_seconds"].get<double>() / 60)
                                      : std::string("—"))
      << " |\n";
  }
  return s.str();
}

// Each row's picture and warnings.
std::string pictures(const std::vector<nlohmann::json>& rows) {
  std::ostringstream s;
  for (const auto& j : rows) {
    s << "**" << row_name(j) << "**, μ = " << fmt("%g", j["mu"]) << "\n\n!["
      << j["scene"].get<std::string>() << "](" << j["picture"].get<std::string>() << ")\n\n";
    for (const auto& w : j["warnings"]) s << "> warning: " << w.get<std::string>() << "\n\n";
  }
  return s.str();
}

// `text` with each `{{key}}` (and a line holding only it, with its newline) replaced.
std::string fill(std::string text, const std::map<std::string, std::string>& values) {
  for (const auto& [key, value] : values) {
    const std::string mark = "{{" + key + "}}";
    for (size_t at; (at = text.find(mark)) != std::string::npos;) {
      const bool line =
          (at == 0 || text[at - 1] == '\n') && text.compare(at + mark.size(), 1, "\n") == 0;
      text.replace(at, mark.size() + (line ? 1 : 0), value);
    }
  }
  return text;
}

// A row's keys the tables read, checked before any is read (a record of another kind in
// docs/results/ used to end `nsf report` with an internal error).
void check_row(const nlohmann::json& j, const std::string& where) {
  for (const char* key : {"scene", "label", "picture"})
    if (!j.contains(key) || !j[key].is_string())
      fail(where, ": a row without a string \"", key, "\" (scene ",
           j.value("scene", nlohmann::json()).dump(),
           "): each *.json there must be a row that nsf report, demo or rom --json wrote");
  for (const char* key : {"mu", "particles", "r", "gamma", "samples", "samples_end", "mean_N",
                          "frames", "speedup", "rom_seconds", "fom_seconds", "fom_peak_mib",
                          "rom_peak_mib", "inference_seconds", "mpm_seconds", "inversion_seconds",
                          "refresh_seconds", "rom_steps_per_frame", "fom_steps_per_frame"})
    if (!j.contains(key) || !j[key].is_number())
      fail(where, ": the row of ", j["scene"].get<std::string>(), " (",
           j["label"].get<std::string>(), ") has no number \"", key, "\"");
}

// What is stored as DIR/*.json, none when DIR does not exist; with results_rows, each checked as
// a row. A file that is not one is named, so that a stray record in the directory is found.
std::vector<nlohmann::json> stored_rows(const std::string& dir, bool results_rows) {
  namespace fs = std::filesystem;
  std::vector<nlohmann::json> rows;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return rows;
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".json") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& p : files) {
    std::ifstream in(p);
    nlohmann::json row = nlohmann::json::parse(in, nullptr, false);
    if (row.is_discarded() || !row.is_object())
      fail(p.string(), ": not a JSON object (a results row, or a summary in generalize/)");
    if (results_rows) check_row(row, p.string());
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace

std::string results_markdown(const std::vector<nlohmann::json>& rows_in, const std::string& command,
                             const std::vector<nlohmann::json>& generalize) {
  std::vector<nlohmann::json> rows = rows_in;
  for (const nlohmann::json& j : rows) check_row(j, "a results row");
  std::sort(rows.begin(), rows.end(), [](const nlohmann::json& a, const nlohmann::json& b) {
    return std::make_pair(a["scene"].get<std::string>(), a["label"].get<std::string>()) <
           std::make_pair(b["scene"].get<std::string>(), b["label"].get<std::string>());
  });
  return fill(results_page_template(),
              {{"command", command},
               {"rows", setup_rows(rows)},
               {"baselines", baseline_rows(rows)},
               {"time", time_rows(rows)},
               {"generalize", generalize.empty() ? "" : "\n" + generalize_markdown(generalize)},
               {"pictures", pictures(rows)}});
}

size_t write_results_page(const std::string& docs) {
  const std::vector<nlohmann::json> rows = stored_rows(docs + "/results", true);
  // The page holds the rows of every size ever made (each kept in results/*.json), so it names
  // both invocations rather than the last one. Written whole or not at all: the old page stays.
  write_file_atomic(docs + "/RESULTS.md",
                    results_markdown(rows,
                                     "nsf report --size small|paper [--quadrature k] [--tracked] "
                                     "[--beyond-sweep] [--decoder F]`, the `*_paper` rows with "
                                     "`--size paper",
                                     stored_rows(docs + "/results/generalize", false)));
  return rows.size();
}

}  // namespace nsf
