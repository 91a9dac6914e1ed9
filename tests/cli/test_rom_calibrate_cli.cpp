// `nsf calibrate` (rom/calibration/latent_prior_calibration.h) on the tiny scene's basis model
// (rom_end_to_end.h): the latent prior and the time step it measures and stores, where `nsf rom`
// and the runtime take them from, and the command's errors, which leave the model as it was.
// GCC 12 reports false -Wmaybe-uninitialized warnings from inside Eigen's AVX-512 kernels for
// dynamic-size matrices (in the intrinsics headers, not in this code).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "cli_runner.h"
#include "nn/dataset.h"
#include "nn/neural_fields.h"
#include "nn/train/trainer.h"
#include "rom/calibration/latent_prior_calibration.h"
#include "rom/calibration/rom_calibration.h"
#include "rom/eval/rom_evaluation.h"
#include "rom/setup/rom_setup.h"
#include "rom_end_to_end.h"

namespace fs = std::filesystem;
using nsf::testing::kTinyScene;
using nsf::testing::RomEndToEnd;
using ::testing::HasSubstr;

namespace {

// The calibration record of model file `path`, as the ROM reads it.
nsf::RomCalibrations stored(const std::string& path) {
  return nsf::rom_calibrations(nsf::NeuralFields::load(path));
}

}  // namespace

// `nsf calibrate` (rom/calibration/latent_prior_calibration.h): each ε's δ is the ROM's on that
// training run, the lowest mean wins, the model file keeps it, and `nsf rom` takes it only where
// neither its command line nor the scene's rom section gives one. Training the model again forgets
// it.
TEST_F(RomEndToEnd, CalibrationStoresTheLatentPriorWithTheLowestMeanDeltaOnTrainingRuns) {
  nsf::CalibrationOptions co = calibration_options("calibrated.nsf");
  const std::string calibrated = co.model_path;
  EXPECT_LT(stored(calibrated).decoded.latent_prior, 0);
  co.grid = {0.0, 0.01, 0.3};  // none, a weak pull, one that pins the latent to the training runs
  const nsf::CalibrationResult r = nsf::calibrate_latent_prior(co);
  ASSERT_EQ(r.runs.size(), 2u);
  ASSERT_EQ(r.delta.size(), 3u);
  EXPECT_EQ(r.runs, (std::vector<std::string>{"train_1.h5", "train_3.h5"}));  // each half's middle
  // δ of one cell, made again by hand: the ROM at that run's μ against that run.
  nsf::RomEvalOptions o = options();
  o.model_path = basis_model();
  o.mu = r.mu[0];
  o.truth_path = (root_ / "data" / r.runs[0]).string();
  o.latent_prior = r.grid[2];
  EXPECT_EQ(nsf::evaluate_rom(o).delta, r.delta[2][0]);
  // The lowest mean of the ε measured on both runs wins; an ε whose first run alone puts its mean
  // above the best before it stops there (it cannot win), its mean then a lower bound.
  size_t best = 0;
  for (size_t g = 0; g < r.grid.size(); ++g)
    if (!r.stopped[g] && r.mean[g] < r.mean[best]) best = g;
  EXPECT_EQ(r.chosen, r.grid[best]);
  EXPECT_FALSE(r.stopped[0]);
  EXPECT_TRUE(r.stopped[2]) << "the strongest prior's first run alone rules it out here";
  for (size_t g = 0; g < r.grid.size(); ++g) {
    if (r.stopped[g]) {
      EXPECT_TRUE(std::isnan(r.delta[g][1]));
      EXPECT_DOUBLE_EQ(r.mean[g], r.delta[g][0] / 2);
      EXPECT_GT(r.mean[g], r.mean[best]);
    } else {
      EXPECT_DOUBLE_EQ(r.mean[g], (r.delta[g][0] + r.delta[g][1]) / 2);
    }
  }
  EXPECT_NE(r.mean[0], r.mean[2]) << "the grid's ends must differ for the choice to mean anything";

  nsf::store_calibration(calibrated, r);
  EXPECT_EQ(stored(calibrated).decoded.latent_prior, r.chosen);
  // The model file written again holds the same fields: a run at a given ε has the same bits.
  o.model_path = calibrated;
  o.latent_prior = r.grid[2];
  EXPECT_EQ(nsf::evaluate_rom(o).delta, r.delta[2][0]);
  const nlohmann::json table = stored(calibrated).decoded.table;
  EXPECT_EQ(table.at("chosen").get<double>(), r.chosen);
  EXPECT_EQ(table.at("grid").size(), 3u);

  // Where ε comes from: the model; the command line; the scene's rom section. (A stored choice
  // of 0.01 m, so that it differs from the default of none.)
  nsf::CalibrationResult forced = r;
  forced.chosen = 0.01;
  nsf::store_calibration(calibrated, forced);
  o = options();
  o.model_path = calibrated;
  nsf::RomReport used = nsf::evaluate_rom(o);
  EXPECT_EQ(used.latent_prior, 0.01);
  EXPECT_EQ(used.latent_prior_source, "model");
  // The runtime (the embedding API, Python, nsf serve) takes it the same way.
  const nsf::NeuralFields cf = nsf::NeuralFields::load(calibrated);
  EXPECT_EQ(nsf::rom_setup(cf, kTinyScene, 1.0, {}, 0).options.latent_prior, 0.01);
  EXPECT_EQ(nsf::rom_setup(nsf::NeuralFields::load_basis(calibrated), kTinyScene, 1.0, {}, 0)
                .options.latent_prior,
            0.01);
  EXPECT_EQ(nsf::rom_setup(cf, kTinyScene, 1.0, {"rom.latent_prior=0.03"}, 0).options.latent_prior,
            0.03);
  o.latent_prior = 0.02;
  used = nsf::evaluate_rom(o);
  EXPECT_EQ(used.latent_prior, 0.02);
  EXPECT_EQ(used.latent_prior_source, "command line");
  o.latent_prior.reset();
  o.overrides = {"rom.latent_prior=0.03"};
  used = nsf::evaluate_rom(o);
  EXPECT_EQ(used.latent_prior, 0.03);
  EXPECT_EQ(used.latent_prior_source, "scene");
  // A setting for the other decoder family is not this (basis) model's; a null in its own
  // family's object hands ε back to the model's calibration. The runtime reads them alike.
  o.overrides = {"rom.latent_prior=0.03", R"(rom.mlp={"latent_prior": 0.05})"};
  EXPECT_EQ(nsf::evaluate_rom(o).latent_prior, 0.03);
  o.overrides = {"rom.latent_prior=0.03", R"(rom.basis={"latent_prior": null})"};
  used = nsf::evaluate_rom(o);
  EXPECT_EQ(used.latent_prior, 0.01);
  EXPECT_EQ(used.latent_prior_source, "model");
  EXPECT_EQ(nsf::rom_setup(cf, kTinyScene, 1.0,
                           {"rom.latent_prior=0.03", R"(rom.basis={"latent_prior": 0.04})"}, 0)
                .options.latent_prior,
            0.04);
  // The tracked state's own calibration: a run whose points carry their stress takes it (the
  // other where the model has none), a run with the decoders' stress never does; the scene's
  // rom.tracked object speaks for tracked runs alone. The runtime reads them alike.
  o.overrides.clear();
  o.rom.fields.stress = "tracked";
  EXPECT_EQ(nsf::evaluate_rom(o).latent_prior, 0.01) << "no tracked calibration yet: the other one";
  nsf::CalibrationResult tracked = r;
  tracked.tracked = true;
  tracked.chosen = 0.02;
  nsf::store_calibration(calibrated, tracked);
  EXPECT_EQ(stored(calibrated).decoded.latent_prior, 0.01);
  EXPECT_EQ(stored(calibrated).tracked.latent_prior, 0.02);
  used = nsf::evaluate_rom(o);
  EXPECT_EQ(used.latent_prior, 0.02);
  EXPECT_EQ(used.latent_prior_source, "model");
  o.overrides = {R"(rom.tracked={"latent_prior": 0.04})"};
  used = nsf::evaluate_rom(o);
  EXPECT_EQ(used.latent_prior, 0.04);
  EXPECT_EQ(used.latent_prior_source, "scene");
  o.rom.fields.stress.clear();
  EXPECT_EQ(nsf::evaluate_rom(o).latent_prior, 0.01);
  const nsf::NeuralFields tf = nsf::NeuralFields::load(calibrated);
  EXPECT_EQ(nsf::rom_setup(tf, kTinyScene, 1.0, {R"(rom.fields={"stress": "tracked"})"}, 0)
                .options.latent_prior,
            0.02);
  EXPECT_EQ(nsf::rom_setup(tf, kTinyScene, 1.0, {}, 0).options.latent_prior, 0.01);

  o = options();  // an uncalibrated model and a scene without one: none
  o.model_path = basis_model();
  used = nsf::evaluate_rom(o);
  EXPECT_EQ(used.latent_prior, 0.0);
  EXPECT_EQ(used.latent_prior_source, "default");

  // h and l trained again on the calibrated model's latents: another ROM, so no calibration (and
  // the bases take the base model's shapes, not the defaults: K 16, coefficient width 64).
  nsf::TrainOptions t;
  t.base_model = calibrated;
  t.config.steps = {1, 20, 20};
  t.config.quiet = true;
  const std::string again = (root_ / "again.nsf").string();
  nsf::train_model((root_ / "data").string(), again, t);
  EXPECT_LT(stored(again).decoded.latent_prior, 0);

  // No scene file to run the ROM on: a clear error, and the model stays as it was.
  co.scene_path.clear();
  auto bytes = [&] {
    std::ifstream in(calibrated, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string before = bytes();
  const nsf::testing::CliResult cli =
      nsf::testing::run_cli("calibrate '" + calibrated + "' '" + co.data_dir + "' --scene '" +
                            (root_ / "missing.json").string() + "' -q");
  EXPECT_NE(cli.exit_code, 0);
  EXPECT_THAT(cli.output, HasSubstr("missing.json"));
  EXPECT_EQ(bytes(), before);
}

// `nsf calibrate --dt-ratios`: at the chosen ε, each ratio's δ is the ROM's at that step on the
// same runs; the largest ratio whose mean stays within the tolerance of the best's is stored, and
// `nsf rom` (and the runtime) take it where neither the command line nor the scene sets a step.
// A sweep with a "vary" axis: each training run is more than its μ, and the calibration's ROM runs
// each at its own values (here the bar's stiffness, which the tracked state's material law reads),
// as the run file holds them. δ of a cell made again by hand with that value matches; at μ alone
// (the scene's own stiffness) it does not.
TEST_F(RomEndToEnd, CalibrationRunsEachTrainingRunOfAMultiAxisSweepAtItsOwnValues) {
  nsf::SweepOptions so;
  so.out_dir = (root_ / "data_vary").string();
  so.jobs = 2;
  so.quiet = true;
  so.overrides = {R"(sweep.vary=[{"name": "stiffness", "range": [12000, 30000],
                                   "set": ["objects[0].material.E={v}"]}])"};
  nsf::run_sweep(kTinyScene, so);
  nsf::CalibrationOptions co = calibration_options("vary_calibrated.nsf");
  co.data_dir = so.out_dir;
  co.overrides = {R"(rom.fields={"stress": "tracked"})"};
  co.grid = {0.0};
  const nsf::CalibrationResult r = nsf::calibrate_latent_prior(co);
  ASSERT_EQ(r.runs.size(), 2u);
  const nsf::Dataset data(so.out_dir);
  for (size_t k = 0; k < r.runs.size(); ++k) {
    SCOPED_TRACE(r.runs[k]);
    double stiffness = -1;
    for (const nsf::SimulationFile& f : data.train())
      if (fs::path(f.path).filename() == r.runs[k])
        for (const nsf::ParameterRange& p : f.box.parameters)
          if (p.name == "stiffness") stiffness = p.lo;
    ASSERT_GT(stiffness, 12000);
    nsf::RomEvalOptions o = options();
    o.model_path = basis_model();
    o.mu = r.mu[k];
    o.truth_path = (fs::path(so.out_dir) / r.runs[k]).string();
    o.latent_prior = 0.0;
    o.overrides = so.overrides;
    o.overrides.push_back(co.overrides[0]);
    EXPECT_NE(nsf::evaluate_rom(o).delta, r.delta[0][k]) << "at μ alone";
    o.overrides.push_back("objects[0].material.E=" + nlohmann::json(stiffness).dump());
    EXPECT_EQ(nsf::evaluate_rom(o).delta, r.delta[0][k]);
  }
}

TEST_F(RomEndToEnd, CalibrationChoosesTheLargestStepWithinTheToleranceAndStoresIt) {
  nsf::CalibrationOptions co = calibration_options("step_calibrated.nsf");
  const std::string calibrated = co.model_path;
  EXPECT_LT(stored(calibrated).decoded.dt_ratio, 0);
  co.grid = {0.0};
  co.dt_ratios = {4, 7.5, 15};  // 4, 2 and 1 ROM steps a frame of 15 substeps
  co.dt_tolerance = 100;        // every ratio that runs qualifies: the largest is chosen
  const nsf::CalibrationResult loose = nsf::calibrate_latent_prior(co);
  ASSERT_TRUE(loose.step.has_value());
  const nsf::StepCalibration& s = *loose.step;
  ASSERT_EQ(s.mean.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    ASSERT_TRUE(std::isfinite(s.mean[i])) << "ratio " << s.ratios[i];
    EXPECT_DOUBLE_EQ(s.mean[i], (s.delta[i][0] + s.delta[i][1]) / 2);
    EXPECT_GT(s.rom_ms_per_frame[i], 0);
  }
  EXPECT_EQ(s.steps_per_frame, (std::vector<int>{4, 2, 1}));
  EXPECT_EQ(s.chosen, 15);
  // δ of one cell, made again by hand: the ROM at that run's μ, at that step.
  nsf::RomEvalOptions o = options();
  o.model_path = basis_model();
  o.mu = loose.mu[1];
  o.truth_path = (root_ / "data" / loose.runs[1]).string();
  o.latent_prior = 0.0;
  o.dt_ratio = 7.5;
  EXPECT_EQ(nsf::evaluate_rom(o).delta, s.delta[1][1]);

  // One step a frame is about twice as far off as four (on this machine 3.1 % against 1.5 %), two
  // within a fifth: at 1.5x the best (the first) mean, the middle ratio is the largest that
  // qualifies.
  co.dt_tolerance = 1.5;
  const nsf::CalibrationResult tight = nsf::calibrate_latent_prior(co);
  EXPECT_EQ(tight.step->mean[0], s.mean[0]) << "the same runs, the same bits";
  EXPECT_EQ(tight.step->chosen, 7.5);
  EXPECT_GT(tight.step->mean[2], 1.5 * tight.step->mean[0]);  // measured, or a bound if stopped
  // An absolute budget the largest step's δ stays within admits it all the same.
  co.dt_budget = 0.5;
  EXPECT_EQ(nsf::calibrate_latent_prior(co).step->chosen, 15);

  nsf::store_calibration(calibrated, tight);
  EXPECT_EQ(stored(calibrated).decoded.dt_ratio, 7.5);
  const nlohmann::json table = stored(calibrated).decoded.table;
  EXPECT_EQ(table.at("step").at("chosen").get<double>(), 7.5);
  EXPECT_EQ(table.at("step").at("ratios").size(), 3u);
  // Where the step comes from: the model; the command line; the scene's rom section.
  o = options();
  o.model_path = calibrated;
  nsf::RomReport used = nsf::evaluate_rom(o);
  EXPECT_EQ(used.dt_ratio, 7.5);
  EXPECT_EQ(used.dt_ratio_source, "model");
  EXPECT_EQ(used.rom_steps_per_frame, 2);
  const nsf::NeuralFields cf = nsf::NeuralFields::load(calibrated);
  EXPECT_EQ(nsf::rom_setup(cf, kTinyScene, 1.0, {}, 0).options.dt_ratio, 7.5);
  EXPECT_EQ(nsf::rom_setup(cf, kTinyScene, 1.0, {"rom.dt_ratio=2"}, 0).options.dt_ratio, 2);
  o.dt_ratio = 1;
  used = nsf::evaluate_rom(o);
  EXPECT_EQ(used.dt_ratio_source, "command line");
  EXPECT_EQ(used.rom_steps_per_frame, 15);
  o.dt_ratio.reset();
  o.overrides = {"rom.dt_ratio=3"};
  used = nsf::evaluate_rom(o);
  EXPECT_EQ(used.dt_ratio_source, "scene");
  EXPECT_EQ(used.rom_steps_per_frame, 5);
  o = options();
  EXPECT_EQ(nsf::evaluate_rom(o).dt_ratio_source, "default");

  // Ratios out of order are a clear error, and the model stays as it was.
  const nsf::testing::CliResult cli =
      nsf::testing::run_cli("calibrate '" + calibrated + "' '" + co.data_dir + "' --scene '" +
                            kTinyScene + "' --grid 0 --runs 1 --dt-ratios 2,1 -q");
  EXPECT_NE(cli.exit_code, 0);
  EXPECT_THAT(cli.output, HasSubstr("ascending"));
  EXPECT_EQ(stored(calibrated).decoded.dt_ratio, 7.5);
}
