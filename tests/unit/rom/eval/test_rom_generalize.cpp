// `nsf generalize` (rom/eval/generalize.h): the benchmark of unseen interactions on the tiny
// scene's "generalize" section, with a tiny per-point basis model trained on its sweep. Each draw
// is run at full order, by the ROM and by the baselines; a draw reruns alone to the same figures.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "data/sweep.h"
#include "error_matchers.h"
#include "nn/torch_settings.h"
#include "nn/train/trainer.h"
#include "rom/calibration/latent_prior_calibration.h"
#include "rom/calibration/rom_calibration.h"
#include "rom/eval/generalize.h"
#include "rom/setup/scene_file.h"

namespace {

namespace fs = std::filesystem;

const std::string kTinyScene =
    (fs::path(NSF_SOURCE_DIR) / "scenes" / "examples" / "rom_tiny.json").string();

class Generalize : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    nsf::set_nn_threads(2);
    root_ = fs::temp_directory_path() / ("nsf_generalize_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    nsf::SweepOptions so;
    so.out_dir = data();
    so.jobs = 2;
    so.quiet = true;
    nsf::run_sweep(kTinyScene, so);
    nsf::TrainOptions o;
    nsf::TrainConfig& c = o.config;
    c.net.decoder = nsf::DecoderFamily::basis;
    c.net.latent_dim = 4;
    c.net.depth = 4;
    c.net.width_g = 64;
    c.net.modes = {16, 16, 16};
    c.net.coefficient_width = 64;
    c.net.coefficient_depth = 2;
    c.steps = {800, 300, 300};
    c.frames_per_batch = {4, 32, 32};
    c.particles_per_frame = {256, 256, 256};
    c.seed = 2;
    c.quiet = true;
    nsf::train_model(data(), model(), o);
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }
  static std::string data() { return (root_ / "data").string(); }
  static std::string model() { return (root_ / "tiny_basis.nsf").string(); }
  static nsf::GeneralizeOptions options() {
    nsf::GeneralizeOptions o;
    o.model_path = model();
    o.data_dir = data();
    o.scene_path = kTinyScene;
    o.draws = 2;
    o.rom.threads = 2;
    o.quiet = true;
    return o;
  }
  static fs::path root_;
};
fs::path Generalize::root_;

TEST_F(Generalize, EachDrawIsScoredWithItsBaselinesAndTheSummaryHasTheIssuesKeys) {
  const nsf::GeneralizeResult r = nsf::run_generalize(options());
  ASSERT_EQ(r.draws.size(), 2u);
  for (const nsf::GeneralizeDraw& g : r.draws) {
    SCOPED_TRACE(g.draw.perturbation);
    ASSERT_TRUE(g.report) << g.error;
    EXPECT_TRUE(g.report->delta > 0 && g.report->delta < 0.5) << g.report->delta;
    EXPECT_GT(g.report->baselines.lookup_delta, 0);
    EXPECT_GT(g.report->baselines.interp_delta, 0);
    EXPECT_GT(g.report->baselines.coarse_delta, 0);
    ASSERT_TRUE(g.report->budget);
    EXPECT_GE(g.report->budget->encoded.delta, 0);
    EXPECT_GT(g.report->residual_cells_mean, 0);
    EXPECT_GE(g.draw.mu, 0.5);
    EXPECT_LE(g.draw.mu, 1.5);
  }
  EXPECT_EQ(r.draws[0].draw.perturbation, "spun about z");
  EXPECT_EQ(r.draws[1].draw.perturbation, "floor tilted");
  const nlohmann::json j = nsf::generalize_json(r, "nsf generalize test");
  for (const char* key :
       {"scene", "draws", "median_delta", "worst_delta", "median_representation_delta",
        "median_speedup", "median_real_time_factor", "win_rate_lookup", "win_rate_interp",
        "win_rate_coarse", "bar", "meets_bar", "command"})
    EXPECT_TRUE(j.contains(key)) << key;
  for (const auto& d : j["draws"])
    for (const char* key :
         {"delta", "speedup", "representation_delta", "lookup_delta", "interp_delta",
          "coarse_delta", "coarse_speedup", "indicator", "perturbation", "value", "mu", "set"})
      EXPECT_TRUE(d.contains(key)) << key;
  // The median of two draws is their mean; the worst is the larger.
  const double d0 = r.draws[0].report->delta, d1 = r.draws[1].report->delta;
  EXPECT_DOUBLE_EQ(j["median_delta"].get<double>(), 0.5 * (d0 + d1));
  EXPECT_DOUBLE_EQ(j["worst_delta"].get<double>(), std::max(d0, d1));
  const double wins = (d0 < r.draws[0].report->baselines.lookup_delta) +
                      (d1 < r.draws[1].report->baselines.lookup_delta);
  EXPECT_DOUBLE_EQ(j["win_rate_lookup"].get<double>(), wins / 2);
  EXPECT_NE(nsf::format_generalize(j).find("floor tilted"), std::string::npos);
  // Each indicator's rank correlation with δ, over the draws: with two, none (ρ needs three).
  for (const auto& d : j["draws"]) EXPECT_GT(d["energy_kept"].get<double>(), 0);  // may pass 1
  for (const char* key : {"indicator_rank_correlation", "training_distance_rank_correlation",
                          "energy_lost_rank_correlation"})
    EXPECT_TRUE(j.contains(key) && j[key].is_null()) << key;
  // Three draws whose lost energy orders them as δ does: ρ = 1; the other way round: −1.
  nsf::GeneralizeResult three;
  for (int k = 0; k < 3; ++k) {
    nsf::GeneralizeDraw g = r.draws[0];
    g.report->delta = 0.01 * (k + 1);
    g.report->energy_kept = 0.9 - 0.1 * k;
    three.draws.push_back(g);
  }
  EXPECT_DOUBLE_EQ(nsf::generalize_json(three, "x")["energy_lost_rank_correlation"], 1.0);
  for (int k = 0; k < 3; ++k) three.draws[size_t(k)].report->energy_kept = 0.7 + 0.1 * k;
  EXPECT_DOUBLE_EQ(nsf::generalize_json(three, "x")["energy_lost_rank_correlation"], -1.0);
  EXPECT_NE(nsf::generalize_markdown({j}).find("rom_tiny"), std::string::npos);

  // Draw 1 again, alone: the same case and the same figures (the engine and the ROM are
  // deterministic for a given seed).
  nsf::GeneralizeOptions one = options();
  one.only = {1};
  const nsf::GeneralizeResult again = nsf::run_generalize(one);
  ASSERT_EQ(again.draws.size(), 1u);
  ASSERT_TRUE(again.draws[0].report);
  EXPECT_EQ(again.draws[0].draw.value, r.draws[1].draw.value);
  EXPECT_EQ(again.draws[0].draw.overrides, r.draws[1].draw.overrides);
  EXPECT_EQ(again.draws[0].report->delta, d1);
  EXPECT_EQ(again.draws[0].report->baselines.coarse_delta,
            r.draws[1].report->baselines.coarse_delta);
}

// A draw lies outside the model's training family: it reads the scene's unseen profile, unless
// the options (`nsf generalize --profile family`) ask for the family's; its row says which.
TEST_F(Generalize, ADrawReadsTheUnseenProfileUnlessTheFamilysIsAskedFor) {
  nsf::GeneralizeOptions o = options();
  o.only = {1};
  o.overrides = {R"(rom.unseen={"samples": 40})"};
  const nsf::GeneralizeResult unseen = nsf::run_generalize(o);
  o.rom.profile = "family";
  const nsf::GeneralizeResult family = nsf::run_generalize(o);
  ASSERT_EQ(unseen.draws.size(), 1u);
  ASSERT_EQ(family.draws.size(), 1u);
  ASSERT_TRUE(unseen.draws[0].report) << unseen.draws[0].error;
  ASSERT_TRUE(family.draws[0].report) << family.draws[0].error;
  EXPECT_FALSE(unseen.draws[0].report->outside_family.empty());
  EXPECT_EQ(unseen.draws[0].report->profile, "unseen");
  EXPECT_EQ(unseen.draws[0].report->samples, 40u);
  EXPECT_EQ(family.draws[0].report->profile, "family");
  EXPECT_NE(family.draws[0].report->samples, 40u);
  const nlohmann::json j = nsf::generalize_json(unseen, "nsf generalize test");
  EXPECT_EQ(j["draws"][0]["profile"], "unseen");
  EXPECT_FALSE(j["draws"][0]["outside_family"].empty());
  EXPECT_EQ(j["rom"]["profile"], "unseen");
}

// QDEIM's samples (rom.sampling = qdeim) on a draw keep g's tangents on S well conditioned.
TEST_F(Generalize, QdeimSamplesKeepTheInversionWellConditionedOnADraw) {
  nsf::GeneralizeOptions o = options();
  o.only = {0};
  const nsf::GeneralizeResult plain = nsf::run_generalize(o);
  o.overrides = {"rom.sampling=qdeim"};
  const nsf::GeneralizeResult qdeim = nsf::run_generalize(o);
  for (const nsf::GeneralizeResult* r : {&plain, &qdeim}) {
    ASSERT_EQ(r->draws.size(), 1u);
    ASSERT_TRUE(r->draws[0].report) << r->draws[0].error;
    EXPECT_TRUE(r->draws[0].report->delta > 0 && r->draws[0].report->delta < 0.5);
  }
  const nsf::RomReport &a = *plain.draws[0].report, &b = *qdeim.draws[0].report;
  EXPECT_EQ(a.sample_condition, -1);
  EXPECT_EQ(b.sampling, "qdeim");
  // The stated conditioning: the orthonormal tangent basis restricted to QDEIM's |S| = 64
  // samples stays within a factor 30 of the best possible (1).
  EXPECT_GE(b.sample_condition, 1.0);
  EXPECT_LT(b.sample_condition, 30.0);
  EXPECT_NE(b.delta, a.delta);
}

// `nsf calibrate --unseen`: the unseen profile's ε chosen on perturbed cases, each against its
// own full-order run, drawn from the scene's calibration seed and never the benchmark's. A run on
// that profile takes it where the profile sets none; a run in the family never does; the benchmark
// refuses to score the model on the draws that calibrated it.
TEST_F(Generalize, TheUnseenProfileIsCalibratedOnPerturbedCasesNeverTheBenchmarks) {
  const std::string calibrated = (root_ / "unseen_calibrated.nsf").string();
  fs::copy_file(model(), calibrated, fs::copy_options::overwrite_existing);
  const std::string profile = R"(rom.unseen={"samples": 48})";
  nsf::CalibrationOptions co;
  co.model_path = calibrated;
  co.data_dir = data();
  co.scene_path = kTinyScene;
  co.overrides = {profile};
  co.unseen = true;
  co.draws = 2;
  co.grid = {0.0, 0.3};  // none, and one that pins the latent to the training runs
  co.threads = 2;
  co.quiet = true;
  const nsf::CalibrationResult r = nsf::calibrate_latent_prior(co);
  EXPECT_TRUE(r.unseen);
  EXPECT_EQ(r.seed, 1001u) << "the scene's generalize.seed (1) + 1000";
  ASSERT_EQ(r.runs.size(), 2u);
  EXPECT_EQ(r.runs[0].rfind("draw 0 (spun about z, v = ", 0), 0u) << r.runs[0];
  EXPECT_EQ(r.runs[1].rfind("draw 1 (floor tilted, v = ", 0), 0u) << r.runs[1];
  // Not the benchmark's cases: the same perturbations at other values.
  const nsf::SceneFile file = nsf::read_scene_file(kTinyScene);
  const nsf::SweepSpec* sweep = &*file.sections.sweep;
  const auto bench = nsf::plan_draws(*file.sections.generalize, sweep, 2, 1);
  const auto own = nsf::plan_draws(*file.sections.generalize, sweep, 2, 1001);
  for (size_t k = 0; k < 2; ++k) {
    EXPECT_NE(own[k].value, bench[k].value);
    EXPECT_EQ(r.mu[k], own[k].mu);
  }
  // δ of one cell made again by hand: the ROM on the unseen profile at that draw, against a fresh
  // full-order run of it.
  nsf::RomEvalOptions ro;
  ro.model_path = calibrated;
  ro.scene_path = kTinyScene;
  ro.overrides = {profile};
  nsf::set_up_draw(ro, own[1], sweep);
  ro.profile = "unseen";
  ro.latent_prior = r.grid[0];
  ro.threads = 2;
  ro.quiet = true;
  const nsf::RomReport by_hand = nsf::evaluate_rom(ro);
  EXPECT_EQ(by_hand.profile, "unseen");
  EXPECT_EQ(by_hand.samples, 48u);
  EXPECT_NEAR(by_hand.delta, r.delta[0][1], 1e-9 + 1e-6 * by_hand.delta);
  EXPECT_NE(r.mean[0], r.mean[1]) << "the grid's ends must differ for the choice to mean anything";
  const size_t best = r.mean[0] <= r.mean[1] ? 0 : 1;
  EXPECT_EQ(r.chosen, r.grid[best]);

  // Stored as the unseen calibration, beside the training runs' (none here).
  nsf::CalibrationResult stored = r;
  stored.chosen = 0.02;  // a value no default gives, to see where it goes
  nsf::store_calibration(calibrated, stored);
  const nsf::RomCalibrations c = nsf::rom_calibrations(nsf::NeuralFields::load(calibrated));
  EXPECT_EQ(c.unseen.latent_prior, 0.02);
  EXPECT_EQ(c.unseen.table.value("seed", 0), 1001);
  EXPECT_LT(c.decoded.latent_prior, 0);
  // A run on the unseen profile takes it; the scene's own value wins over it; the family never.
  ro.latent_prior.reset();
  ro.full_order = false;
  ro.truth_path.clear();
  nsf::RomReport used = nsf::evaluate_rom(ro);
  EXPECT_EQ(used.latent_prior, 0.02);
  EXPECT_EQ(used.latent_prior_source, "model");
  ro.overrides = {R"(rom.unseen={"samples": 48, "latent_prior": 0.04})"};
  used = nsf::evaluate_rom(ro);
  EXPECT_EQ(used.latent_prior, 0.04);
  EXPECT_EQ(used.latent_prior_source, "scene");
  ro.profile = "family";
  used = nsf::evaluate_rom(ro);
  EXPECT_EQ(used.latent_prior, 0.0);
  EXPECT_EQ(used.latent_prior_source, "default");

  // The benchmark on the calibration's seed is refused, before any draw runs.
  nsf::GeneralizeOptions g = options();
  g.model_path = calibrated;
  g.seed = 1001;
  nsf::testing::expect_error([&] { nsf::run_generalize(g); },
                             {"calibrated on the draws of seed 1001"});
  // Calibrating on the benchmark's seed, or a scene without an unseen profile: clear errors.
  co.seed = 1;
  nsf::testing::expect_error([&] { nsf::calibrate_latent_prior(co); }, {"is the benchmark's"});
  co.seed.reset();
  co.overrides.clear();
  nsf::testing::expect_error([&] { nsf::calibrate_latent_prior(co); },
                             {"has no rom.unseen profile to calibrate"});
}

TEST_F(Generalize, ASceneWithoutPerturbationsOrAMissingDrawIsAClearError) {
  nsf::GeneralizeOptions o = options();
  o.overrides = {"generalize=null"};
  try {
    nsf::run_generalize(o);
    ADD_FAILURE() << "accepted a scene without perturbations";
  } catch (const nsf::Error& e) {
    nsf::testing::expect_contains(e.what(), "has no \"generalize\" section");
  }
  o = options();
  o.model_path = (root_ / "missing.nsf").string();
  try {
    nsf::run_generalize(o);
    ADD_FAILURE() << "accepted a missing model";
  } catch (const nsf::Error& e) {
    nsf::testing::expect_contains(e.what(), "missing.nsf");
  }
  // A sweep with an axis the dataset's runs were not made along: said before any draw runs.
  o = options();
  o.overrides = {R"(sweep.vary=[{"name": "stiffness", "range": [15000, 25000],
                                  "set": ["objects[0].material.E={v}"]}])"};
  try {
    nsf::run_generalize(o);
    ADD_FAILURE() << "accepted a dataset without the sweep's axis";
  } catch (const nsf::Error& e) {
    nsf::testing::expect_contains(e.what(), "has no value of the sweep's axis 'stiffness'");
  }
  o = options();
  o.only = {5};
  try {
    nsf::run_generalize(o);
    ADD_FAILURE() << "accepted draw 5 of 2";
  } catch (const nsf::Error& e) {
    nsf::testing::expect_contains(e.what(), "draw 5 does not exist");
  }
}

}  // namespace

// docs/RESULTS.md's table by kind of perturbation: each kind's medians, and a failed ROM draw
// shown as failed and counted as a loss even where the draw never reached its baselines.
TEST(GeneralizePage, DrawsByKindCountAFailedRomAsALoss) {
  nlohmann::json row = {{"scene", "bread_tiny"}, {"command", "nsf generalize x"}};
  row["draws"] = nlohmann::json::array({{{"perturbation", "grips slower"},
                                         {"delta", 0.01},
                                         {"representation_delta", 0.002},
                                         {"lookup_delta", 0.04},
                                         {"interp_delta", 0.03}},
                                        {{"perturbation", "weak scattered"}, {"failed", true}},
                                        {{"perturbation", "grips slower"},
                                         {"delta", 0.03},
                                         {"representation_delta", 0.004},
                                         {"lookup_delta", 0.02},
                                         {"interp_delta", 0.03}}});
  const std::string md = nsf::generalize_markdown({row});
  EXPECT_NE(
      md.find("| bread_tiny | grips slower | 2 | 2.00 % | 0.30 % | 3.00 % | 3.00 % | 1 of 2 |"),
      std::string::npos)
      << md;
  EXPECT_NE(md.find("| bread_tiny | weak scattered | 1 | failed | — | — | — | 0 of 1 |"),
            std::string::npos)
      << md;
}
