// docs/RESULTS.md is rebuilt from stored rows: every measured figure and the paper's appear.
#include <gtest/gtest.h>

#include "core/error.h"
#include "error_matchers.h"
#include "mesh_fixtures.h"
#include "rom/eval/result_row.h"
#include "rom/eval/results_page.h"
#include "rom/eval/rom_evaluation.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

TEST(RomResults, TablePrintsMeasuredAndPaperFiguresPerScene) {
  nsf::RomReport r;
  r.scene = "sand_small";
  r.mu = 31.25;
  r.has_mu = true;
  r.particles = 12000;
  r.latent_dim = 6;
  r.gamma = 6000;
  r.samples = r.samples_end = 50;
  r.mean_N = 3456;
  r.delta = 0.0123;
  r.latent_prior = 0.002;
  r.stress_error = 0.712;
  r.frames = 10;
  r.rom_seconds = 2.0;
  r.fom_seconds = 5.0;
  r.rom_peak_mib = 300, r.fom_peak_mib = 400;
  r.rom_steps_per_frame = 20, r.fom_steps_per_frame = 30;
  r.threads = 1;
  r.field_sources = "x from g's basis, tau from h's basis, C from l's basis";
  const auto row = nsf::result_json(r, "scenes/paper/sand_small.json", "models/sand_small.nsf",
                                    "results/sand_small.png", "");
  const std::string md = nsf::results_markdown({row}, "nsf report --size small");
  for (const char* part :
       {"`nsf report --size small`", "| sand_small | 31.25 | 12000 | 6 | bases | 6e+03 |",
        "| 50 | 3456 | 2 mm | 1.23% | 71% | 2.50× | 200.0 | 500.0 | 400 / 300 |",
        "| 20 | 30 | 1 | — |", "71,363, 0.4%", "results/sand_small.png"})
    EXPECT_NE(md.find(part), std::string::npos) << "missing '" << part << "' in\n" << md;
  // The baselines' section: a dash for each one the row did not measure.
  EXPECT_NE(md.find("| sand_small | 31.25 | 1.23% | 2.50× | — | — | — | — | — |"),
            std::string::npos)
      << md;
  // The model's training time, where the row records it (rows before it: the dash above).
  r.train_seconds = 450;
  EXPECT_NE(nsf::results_markdown({nsf::result_json(r, "s.json", "m.nsf", "p.png", "")}, "nsf")
                .find("| 20 | 30 | 1 | 7.5 min |"),
            std::string::npos);
  r.baselines.lookup_delta = 0.004, r.baselines.lookup_mu = 30;
  r.baselines.interp_delta = 0.0021, r.baselines.interp_mu_lo = 27.5;
  r.baselines.interp_mu_hi = 30, r.baselines.interp_extrapolated = true;
  r.baselines.coarse_delta = 0.03, r.baselines.coarse_seconds = 0.5;
  r.baselines.coarse_particles = 1500, r.baselines.coarse_scene = "sand_small at 1.5x dx";
  const auto with = nsf::result_json(r, "s.json", "m.nsf", "p.png", "");
  EXPECT_EQ(with.at("coarse_speedup").get<double>(), 10.0);  // 5 s of full order over 0.5 s
  const std::string md_with = nsf::results_markdown({with}, "nsf report");
  EXPECT_NE(md_with.find("| 0.40% (30) | 0.21% (extrapolated) | 3.00% | 10.00× | sand_small at "
                         "1.5x dx, 1500 particles |"),
            std::string::npos)
      << md_with;
  // Rows stored before the stress error was measured show a dash, not a made-up figure.
  nlohmann::json old = row;
  old.erase("stress_error");
  old.erase("latent_prior");
  old.erase("field_sources");
  const std::string md_old = nsf::results_markdown({old}, "nsf report");
  EXPECT_NE(md_old.find("| 3456 | — | 1.23% | — | 2.50× |"), std::string::npos) << md_old;
  EXPECT_NE(md_old.find("| 6 | MLP | 6e+03 |"), std::string::npos) << md_old;
  // A quadrature thinned by the scene's rom section, not by `nsf report --quadrature`, is named.
  r.quadrature_points = 1500;
  r.quadrature_per_cell = 1;
  nlohmann::json scenes = nsf::result_json(r, "s.json", "m.nsf", "p.png", "");
  EXPECT_NE(nsf::results_markdown({scenes}, "nsf")
                .find("| sand_small (quadrature 1/cell, the "
                      "scene's) | 31.25 |"),
            std::string::npos);
  scenes.erase("quadrature_per_cell");  // rows stored before it was
  EXPECT_NE(nsf::results_markdown({scenes}, "nsf")
                .find("**sand_small (thinned quadrature, the "
                      "scene's)**"),
            std::string::npos);
  const std::string labelled = nsf::results_markdown(
      {nsf::result_json(r, "s.json", "m.nsf", "p.png", "quadrature 1/cell")}, "nsf");
  EXPECT_NE(labelled.find("| sand_small (quadrature 1/cell) | 31.25 |"), std::string::npos)
      << labelled;
  r.quadrature_points = r.particles;  // every particle
  EXPECT_NE(nsf::results_markdown({nsf::result_json(r, "s.json", "m.nsf", "p.png", "")}, "nsf")
                .find("| sand_small | 31.25 |"),
            std::string::npos);
}

// `nsf report --check`: a rerun must give every figure but the machine's bit for bit; timings,
// memory, speed-ups and the thread count may differ, and keys recorded since the row was made
// are not differences, nor is where a setting came from (the setting is compared) or the model
// file's checksum.
TEST(RomResults, ARerunDiffersOnlyWhereAFigureDoes) {
  nsf::RomReport r;
  r.scene = "metal_small";
  r.mu = 0.027;
  r.delta = 0.0050812345678901;
  r.stress_error = 0.6;
  r.rom_seconds = 1.0, r.fom_seconds = 3.0;
  r.rom_peak_mib = 280;
  r.threads = 1;
  r.cpu = "AMD EPYC 7B13";
  r.baselines.lookup_delta = 0.0044, r.baselines.lookup_mu = 0.018;
  r.latent_prior = 0.0003, r.latent_prior_source = "model";
  const auto stored = nsf::result_json(r, "scenes/paper/metal_small.json", "models/metal_small.nsf",
                                       "results/metal_small.png", "");
  nsf::RomReport again = r;
  again.rom_seconds = 1.3, again.fom_seconds = 2.7, again.rom_peak_mib = 290, again.threads = 2;
  again.cpu = "Intel(R) Xeon(R) Processor @ 2.50GHz";  // another machine: a timing, not a figure
  EXPECT_EQ(stored.at("cpu"), "AMD EPYC 7B13");
  again.model_checksum = "1a2b3c4d";           // recorded only by the rerun
  again.latent_prior_source = "command line";  // --check hands it the stored prior; it was "model"
  EXPECT_TRUE(
      nsf::row_differences(stored, nsf::result_json(again, "scenes/paper/metal_small.json",
                                                    "models/metal_small.nsf", "results/x.png", ""))
          .empty());
  // A recalibrated model file (another checksum) that gives every figure again reproduces.
  r.model_checksum = "5e6f7a8b";
  EXPECT_TRUE(nsf::row_differences(
                  nsf::result_json(r, "scenes/paper/metal_small.json", "models/metal_small.nsf",
                                   "results/metal_small.png", ""),
                  nsf::result_json(again, "scenes/paper/metal_small.json", "models/metal_small.nsf",
                                   "results/x.png", ""))
                  .empty());
  again.delta = std::nextafter(r.delta, 1.0);  // the last bit
  again.baselines.lookup_delta = -1;           // not measured by the rerun
  const std::vector<std::string> d = nsf::row_differences(
      stored, nsf::result_json(again, "scenes/paper/metal_small.json", "models/metal_small.nsf",
                               "results/metal_small.png", ""));
  ASSERT_EQ(d.size(), 6u);  // delta, then the interpolation's three keys and look-up's two
  EXPECT_EQ(d[0].rfind("delta: stored 0.0050812345678901", 0), 0u) << d[0];
  EXPECT_NE(d[1].find("not in the rerun"), std::string::npos) << d[1];
}

// The page is rebuilt from every stored row, whichever command stored it (`nsf report`, `nsf
// demo --docs`), and replaces the old page whole.
TEST(RomResults, ThePageIsRebuiltFromEveryStoredRow) {
  namespace fs = std::filesystem;
  const nsf::testing::TempDir dir("results_page");
  const fs::path& docs = dir.path();
  fs::create_directories(docs / "results");
  nsf::RomReport r;
  r.particles = 100, r.frames = 2, r.delta = 0.01, r.rom_seconds = 1, r.fom_seconds = 3;
  for (const char* scene : {"metal_small", "sand_small"}) {
    r.scene = scene;
    std::ofstream(docs / "results" / (std::string(scene) + ".json")) << nsf::result_json(
        r, "s.json", "m.nsf", "p.png", scene == std::string("metal_small") ? "demo" : "");
  }
  std::ofstream(docs / "RESULTS.md") << "an old page\n";
  EXPECT_EQ(nsf::write_results_page(docs.string()), 2u);
  std::ifstream in(docs / "RESULTS.md");
  const std::string md((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(md.find("an old page"), std::string::npos);
  EXPECT_NE(md.find("metal_small (demo)"), std::string::npos) << md;
  EXPECT_NE(md.find("| sand_small |"), std::string::npos) << md;
  EXPECT_FALSE(fs::exists(docs / "RESULTS.md.tmp"));
  // A page that cannot be written is a named error, and the old page stays as it was.
  fs::create_directories(docs / "RESULTS.md.tmp" / "blocked");
  EXPECT_THROW(nsf::write_results_page(docs.string()), nsf::Error);
  std::ifstream again(docs / "RESULTS.md");
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(again)), std::istreambuf_iterator<char>()),
            md);
}

}  // namespace

namespace {

namespace fs = std::filesystem;
using nsf::testing::error_of;

// A record of another kind in docs/results/ (a tool's JSON, a damaged row) is named with its
// file, and the page stays as it was: it used to end `nsf report` with an internal error.
TEST(RomResults, AStrayRecordAmongTheRowsIsANamedErrorAndThePageStays) {
  const fs::path docs = fs::temp_directory_path() / "nsf_results_stray";
  fs::remove_all(docs);
  fs::create_directories(docs / "results");
  nsf::RomReport r;
  r.scene = "metal_small", r.particles = 100, r.frames = 2, r.rom_seconds = 1, r.fom_seconds = 3;
  std::ofstream(docs / "results" / "metal_small.json")
      << nsf::result_json(r, "s.json", "m.nsf", "p.png", "");
  std::ofstream(docs / "RESULTS.md") << "the old page\n";
  std::ofstream(docs / "results" / "tool_check.json") << R"({"command": "pvpython x", "ok": true})";
  EXPECT_NE(error_of([&] {
              nsf::write_results_page(docs.string());
            }).find("tool_check.json: a row without a string \"scene\""),
            std::string::npos);
  std::ofstream(docs / "results" / "tool_check.json") << "{not json";
  EXPECT_NE(error_of([&] {
              nsf::write_results_page(docs.string());
            }).find("tool_check.json: not a JSON object"),
            std::string::npos);
  std::ifstream in(docs / "RESULTS.md");
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()),
            "the old page\n");
  fs::remove(docs / "results" / "tool_check.json");
  EXPECT_EQ(nsf::write_results_page(docs.string()), 1u);
  fs::remove_all(docs);
}

}  // namespace
