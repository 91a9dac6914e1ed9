#include "app/results_table.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "core/error.h"
#include "io/atomic_file.h"
#include "rom/eval/generalize.h"

namespace nsf::app {

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

bool machine_key(const std::string& k) {
  const auto ends = [&](const std::string& tail) {
    return k.size() >= tail.size() && k.compare(k.size() - tail.size(), tail.size(), tail) == 0;
  };
  return ends("_seconds") || ends("_mib") || k == "speedup" || k == "coarse_speedup" ||
         k == "threads" || k == "cpu" || k == "picture";
}

// Where a setting came from, not a figure: the setting itself is compared. `--check` hands the
// rerun the stored row's prior and step on its command line, so the source differs by
// construction. Nor is the model file's checksum a figure: a recalibration rewrites the file and
// leaves the decoders as they were (`--check` names a changed file beside its verdict).
bool provenance_key(const std::string& k) {
  return k == "latent_prior_source" || k == "dt_ratio_source" || k == "model_crc32";
}

}  // namespace

std::vector<std::string> row_differences(const nlohmann::json& stored,
                                         const nlohmann::json& fresh) {
  // Keys only the rerun has were recorded after the row was made (model_crc32, say).
  std::vector<std::string> out;
  for (auto it = stored.begin(); it != stored.end(); ++it) {
    const std::string& k = it.key();
    if (machine_key(k) || provenance_key(k)) continue;
    if (!fresh.contains(k))
      out.push_back(k + ": stored " + it->dump() + ", not in the rerun");
    else if (*it != fresh.at(k))
      out.push_back(k + ": stored " + it->dump() + ", now " + fresh.at(k).dump());
  }
  return out;
}

nlohmann::json result_json(const RomReport& r, const std::string& scene_file,
                           const std::string& model_file, const std::string& picture,
                           const std::string& label) {
  nlohmann::json j;
  j["scene"] = r.scene;
  j["label"] = label;
  j["scene_file"] = scene_file;
  j["model_file"] = model_file;
  if (!r.model_checksum.empty()) j["model_crc32"] = r.model_checksum;
  j["picture"] = picture;
  j["mu"] = r.mu;
  j["particles"] = r.particles;
  j["r"] = r.latent_dim;
  j["gamma"] = r.gamma;
  j["samples"] = r.samples;
  j["samples_end"] = r.samples_end;
  j["mean_N"] = r.mean_N;
  j["quadrature_points"] = r.quadrature_points;
  j["quadrature_per_cell"] = r.quadrature_per_cell;
  j["threads"] = r.threads;
  if (!r.cpu.empty()) j["cpu"] = r.cpu;
  j["delta"] = r.delta;
  j["latent_prior"] = r.latent_prior;
  if (r.sample_condition >= 0) {  // QDEIM's samples (rom.sampling = qdeim)
    j["sampling"] = r.sampling;
    j["sample_condition"] = r.sample_condition;
  }
  j["latent_prior_source"] = r.latent_prior_source;
  j["stress_error"] = r.stress_error;
  j["affine_error"] = r.affine_error;
  j["frames"] = r.frames;
  j["rom_seconds"] = r.rom_seconds;
  j["fom_seconds"] = r.fom_seconds;
  j["speedup"] = r.speedup();
  j["inference_seconds"] = r.rom_times.inference.seconds();
  j["mpm_seconds"] = r.rom_times.mpm.seconds();
  j["inversion_seconds"] = r.rom_times.inversion.seconds();
  j["refresh_seconds"] = r.rom_times.refresh.seconds();
  j["rom_peak_mib"] = r.rom_peak_mib;
  j["fom_peak_mib"] = r.fom_peak_mib;
  j["baseline_mib"] = r.baseline_mib;
  j["rom_steps_per_frame"] = r.rom_steps_per_frame;
  j["dt_ratio"] = r.dt_ratio;
  j["dt_ratio_source"] = r.dt_ratio_source;
  j["fom_steps_per_frame"] = r.fom_steps_per_frame;
  j["field_sources"] = r.field_sources;
  if (r.train_seconds > 0) j["train_seconds"] = r.train_seconds;
  if (r.budget) {
    j["delta_encoded"] = r.budget->encoded.delta;
    j["stress_error_encoded"] = r.budget->encoded.stress;
    j["affine_error_encoded"] = r.budget->encoded.affine;
    j["delta_projected"] = r.budget->projected.delta;
    j["stress_error_projected"] = r.budget->projected.stress;
    j["affine_error_projected"] = r.budget->projected.affine;
  }
  // The baselines (rom/eval/baselines.h), where measured.
  const Baselines& b = r.baselines;
  if (b.lookup_delta >= 0) {
    j["lookup_delta"] = b.lookup_delta;
    j["lookup_mu"] = b.lookup_mu;
    j["interp_delta"] = b.interp_delta;
    j["interp_mu"] = {b.interp_mu_lo, b.interp_mu_hi};
    j["interp_extrapolated"] = b.interp_extrapolated;
    if (b.interp_runs > 2) j["interp_runs"] = b.interp_runs;
  }
  if (b.coarse_delta >= 0) {
    j["coarse_delta"] = b.coarse_delta;
    j["coarse_seconds"] = b.coarse_seconds;
    j["coarse_speedup"] = r.coarse_speedup();
    j["coarse_particles"] = b.coarse_particles;
    j["coarse_scene"] = b.coarse_scene;
  }
  j["energy_kept"] = r.energy_kept;
  if (!r.delta_per_frame.empty()) j["delta_per_frame"] = r.delta_per_frame;  // frames 1…N
  j["rom_setup_seconds"] = r.rom_setup_seconds;
  j["warnings"] = r.warnings;
  return j;
}

std::string results_markdown(const std::vector<nlohmann::json>& rows_in, const std::string& command,
                             const std::vector<nlohmann::json>& generalize) {
  std::vector<nlohmann::json> rows = rows_in;
  std::sort(rows.begin(), rows.end(), [](const nlohmann::json& a, const nlohmann::json& b) {
    return std::make_pair(a["scene"].get<std::string>(), a["label"].get<std::string>()) <
           std::make_pair(b["scene"].get<std::string>(), b["label"].get<std::string>());
  });
  std::ostringstream s;
  s << "# Results: the paper's Table 1 on nsf\n\n"
    << "Made by `" << command << "`; one scene's rows are remade alone with "
    << "`nsf report --scenes NAME` (each scene's measurements are kept in "
    << "`docs/results/*.json`, and the page is rebuilt from all of them). Every row is one "
       "reduced-order run at a held-out μ (never in the training set), measured against the "
       "full-order engine on the same scene in the same process, with the same threads (the "
       "last column of the time table; — for rows stored before the count was, which ran with "
       "`nsf report`'s default of 2). "
       "The decoders column names the model's family: per-point bases (the default) or MLP "
       "fields (docs/TRAINING.md, \"Decoder families\"); rows labelled with "
       "the family are `nsf report --decoder` with the family other than the scene's own. "
       "δ is eq. 11 over all particles and frames; speed-up is full-order step time over "
       "ROM step time (output excluded from both); memory is each phase's peak resident "
       "size (the process baseline, mostly LibTorch and the model, is in both). τ error is the "
       "relative error of the ROM's stress (h at its own latents) against the ground truth's "
       "over all particles and frames (— for rows stored before it was measured). Rows "
       "labelled *quadrature k/cell* (`nsf report --quadrature k`, or *the scene's* where the "
       "scene's rom section sets it) integrate the ROM's MPM step "
       "with k points per grid cell of the rest shape, each merging a group of particles (their "
       "mass, volume and centre of mass; docs/ROM.md, \"Thinned quadrature\"), and their mean "
       "|N| counts those points; the others use every particle, as the paper does. The latent "
       "prior column is the ε of the inversion's pull toward the training runs' latents "
       "(the scene's `rom.latent_prior` or the model's calibration, `nsf calibrate`; docs/ROM.md, "
       "\"Latent prior\"; — without one, as in the paper, or for rows stored before it "
       "existed).\n\n";
  s << "| scene | μ | \\|P\\| | r | decoders | γ | \\|S\\| | mean \\|N\\| | latent prior | δ | τ "
       "error | "
       "speed-up | ROM ms/frame | full ms/frame | memory full / ROM (MiB) | paper: \\|P\\|, δ, "
       "\\|S\\|, speed-up, memory |\n"
    << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
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
  s << "\n## Against the simple baselines\n\n"
    << "What a user could run instead, each scored with δ against the same ground truth in the "
       "same `nsf report` run (rom/eval/baselines.h): *look-up* plays back the training run "
       "nearest "
       "in μ; *interpolation* blends the two training runs around μ linearly in μ, frame by "
       "frame (the two nearest, extrapolating, outside the training range); the *coarse engine* "
       "is nsf's full-order engine on the small scene (for a paper-size row) or on the scene at "
       "1.5× Δx (for a small one), every particle following the coarse particles around it in "
       "the rest configuration, with its own speed-up against full order. — for rows stored "
       "before the baselines were measured.\n\n"
    << "| scene | μ | ROM δ | ROM speed-up | look-up δ (run at μ) | interpolation δ | coarse "
       "engine δ | coarse engine speed-up | coarse engine |\n"
    << "|---|---|---|---|---|---|---|---|---|\n";
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
  s << "\n## Where the reduced-order time goes\n\n"
    << "| scene | inference (g on candidates, h, l on N) | MPM on N | Gauss–Newton | "
       "candidate refresh | ROM steps/frame | full-order steps/frame | threads | model's "
       "training |\n"
    << "|---|---|---|---|---|---|---|---|---|\n";
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
  if (!generalize.empty()) s << "\n" << generalize_markdown(generalize);
  s << "\n## Pictures (top: ground truth, bottom: reduced order)\n\n";
  for (const auto& j : rows) {
    s << "**" << row_name(j) << "**, μ = " << fmt("%g", j["mu"]) << "\n\n!["
      << j["scene"].get<std::string>() << "](" << j["picture"].get<std::string>() << ")\n\n";
    for (const auto& w : j["warnings"]) s << "> warning: " << w.get<std::string>() << "\n\n";
  }
  return s.str();
}

// The rows stored as DIR/*.json, none when DIR does not exist.
std::vector<nlohmann::json> stored_rows(const std::string& dir) {
  namespace fs = std::filesystem;
  std::vector<nlohmann::json> rows;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return rows;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".json") {
      std::ifstream in(e.path());
      rows.push_back(nlohmann::json::parse(in));
    }
  return rows;
}

size_t write_results_page(const std::string& docs) {
  const std::vector<nlohmann::json> rows = stored_rows(docs + "/results");
  // The page holds the rows of every size ever made (each kept in results/*.json), so it names
  // both invocations rather than the last one. Written whole or not at all: the old page stays.
  write_file_atomic(docs + "/RESULTS.md",
                    results_markdown(rows,
                                     "nsf report --size small|paper [--quadrature k] [--tracked] "
                                     "[--beyond-sweep] [--decoder F]`, the `*_paper` rows with "
                                     "`--size paper",
                                     stored_rows(docs + "/results/generalize")));
  return rows.size();
}

}  // namespace nsf::app
