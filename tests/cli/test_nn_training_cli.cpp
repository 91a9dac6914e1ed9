// `nsf train` run as a user runs it, beside the training fixture (nn_training_fixture.h): the
// scene's training recipe and the flags that override it, and --base-model's refusals.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "error_matchers.h"
#include "nn/config.h"
#include "nn/model/neural_model.h"
#include "nn/train/trainer.h"
#include "nn_fixtures.h"
#include "nn_training_fixture.h"

namespace fs = std::filesystem;
using nsf::testing::nn_training::kParticles;
using nsf::testing::nn_training::LossCurve;
using nsf::testing::nn_training::NnTraining;
using nsf::testing::nn_training::read_losses;
using nsf::testing::nn_training::tiny_options;

// `nsf train` takes steps, widths and the encoder's length from the "train" section of the scene
// that the dataset's runs were simulated from, where the command line gives none.
TEST_F(NnTraining, TrainCommandFollowsTheScenesRecipe) {
  const fs::path data = root_ / "recipe_data";
  nsf::test::write_synthetic_dataset(
      data, 64, /*seed=*/7, /*frames=*/4, {0.5, 1.0},
      R"({"name": "synthetic", "train": {"steps": [12, 7, 5], "widths": [16, 24, 32],
          "frames_per_batch": [2, 4, 8], "particles_per_frame": [16, 16, 16]}})");
  auto train = [&](const std::string& name, const std::string& flags, std::string& out) {
    const std::string model = (root_ / (name + ".nsf")).string();
    return nsf::testing::run_cli("train '" + data.string() + "' --out '" + model +
                                     "' -j 1 -q --decoder mlp --refine-latents 1 " + flags,
                                 out);
  };
  auto stage_steps = [&](const std::string& name) {
    const LossCurve c = read_losses((root_ / (name + ".loss.csv")).string());
    return std::vector<size_t>{c.loss[0].size(), c.loss[1].size(), c.loss[2].size()};
  };
  std::string out;
  ASSERT_EQ(train("recipe", "", out), 0) << out;
  EXPECT_NE(out.find("widths g 16, h 24, l 32"), std::string::npos) << out;
  EXPECT_EQ(stage_steps("recipe"), (std::vector<size_t>{12, 7, 5}));

  // The recipe's batches: with --epochs, steps = points / (frames × particles per batch), so
  // stage 1 takes twice the steps of stage 2 and four times those of stage 3.
  ASSERT_EQ(train("recipe_batch", "--epochs 1", out), 0) << out;
  std::vector<size_t> n = stage_steps("recipe_batch");
  EXPECT_GE(n[2], 2u);
  EXPECT_EQ(n, (std::vector<size_t>{4 * n[2], 2 * n[2], n[2]})) << out;
  ASSERT_EQ(
      train("recipe_batch_flags", "--epochs 1 --frames-per-batch 8 --particles-per-frame 32", out),
      0)
      << out;
  const size_t half = (n[2] + 1) / 2;  // twice stage 3's batch, steps rounded up
  EXPECT_EQ(stage_steps("recipe_batch_flags"), (std::vector<size_t>{half, half, half}));

  ASSERT_EQ(train("recipe_flags", "--steps 6 --width-h 8 --width-l 12", out), 0) << out;
  EXPECT_NE(out.find("widths g 16, h 8, l 12"), std::string::npos) << out;
  EXPECT_EQ(stage_steps("recipe_flags"), (std::vector<size_t>{6, 6, 6}));
  // --widths, as demo and report spell it (issue #28, item 18): 0 keeps the recipe's width.
  ASSERT_EQ(train("recipe_widths", "--steps 6 --widths 0,8,0", out), 0) << out;
  EXPECT_NE(out.find("widths g 16, h 8, l 32"), std::string::npos) << out;
  ASSERT_EQ(train("recipe_width", "--steps 6 --widths 8", out), 0) << out;
  EXPECT_NE(out.find("widths g 8, h 8, l 8"), std::string::npos) << out;

  ASSERT_EQ(train("recipe_off", "--steps 6 --no-scene-recipe", out), 0) << out;
  const nsf::NetConfig table1 = nsf::default_net_config("synthetic");
  EXPECT_NE(out.find("widths g " + std::to_string(table1.width_g) + ", h " +
                     std::to_string(table1.width_h)),
            std::string::npos)
      << out;

  // The shape flags no scene's recipe sets reach the model: h without μ, and the size of a basis
  // model's coefficient networks.
  ASSERT_EQ(train("no_mu", "--steps 6 --no-mu", out), 0) << out;
  EXPECT_FALSE(nsf::NeuralModel::load((root_ / "no_mu.nsf").string()).stress_has_mu());
  EXPECT_TRUE(nsf::NeuralModel::load((root_ / "recipe_off.nsf").string()).stress_has_mu());
  const std::string coefficients = (root_ / "coefficients.nsf").string();
  ASSERT_EQ(nsf::testing::run_cli(
                "train '" + data.string() + "' --out '" + coefficients +
                    "' -j 1 -q --decoder basis --steps 6 --no-calibrate "
                    "--coefficients network --affine-input latent --coefficient-width 12 "
                    "--coefficient-depth 2",
                out),
            0)
      << out;
  const nsf::NeuralModel basis = nsf::NeuralModel::load(coefficients);
  EXPECT_EQ(basis.config.coefficient_width, 12);
  EXPECT_EQ(basis.config.coefficient_depth, 2);

  // --scene: the recipe of the scene file as edited since the sweep, not the runs' stored one;
  // a file of another scene is refused before anything trains.
  const fs::path edited = root_ / "recipe_edited.json";
  std::ofstream(edited) << R"({"name": "synthetic", "train": {"steps": [5, 4, 3],
                              "widths": [8, 12, 16]}})";
  ASSERT_EQ(train("recipe_file", "--scene '" + edited.string() + "'", out), 0) << out;
  EXPECT_NE(out.find("widths g 8, h 12, l 16"), std::string::npos) << out;
  EXPECT_EQ(stage_steps("recipe_file"), (std::vector<size_t>{5, 4, 3}));
  const fs::path other = root_ / "recipe_other.json";
  std::ofstream(other) << R"({"name": "metal_small", "train": {"steps": [5, 4, 3]}})";
  EXPECT_NE(train("recipe_other", "--scene '" + other.string() + "'", out), 0);
  EXPECT_NE(out.find("its scene is 'metal_small', the dataset's is 'synthetic'"), std::string::npos)
      << out;
  EXPECT_FALSE(fs::exists(root_ / "recipe_other.nsf"));

  // A malformed recipe stops training with the key at fault, and writes no model.
  const fs::path bad = root_ / "recipe_bad";
  nsf::test::write_synthetic_dataset(bad, 64, 7, 4, {0.5, 1.0},
                                     R"({"name": "synthetic", "train": {"steps": [0, 7, 5]}})");
  const std::string model = (root_ / "recipe_bad.nsf").string();
  EXPECT_NE(
      nsf::testing::run_cli("train '" + bad.string() + "' --out '" + model + "' -j 1 -q", out), 0);
  EXPECT_NE(out.find("train.steps[0]"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(model));
}

// `--base-model` keeps a model's encoder and g: a model of another scene or a shape flag beside it
// stops training with a message naming the problem, and writes nothing.
TEST_F(NnTraining, BaseModelOfAnotherSceneOrWithShapeFlagsIsAClearError) {
  const fs::path other = root_ / "base_other_scene";
  nsf::test::write_synthetic_dataset(other, kParticles, /*seed=*/8, /*frames=*/3);
  const std::string out = file("base/synthetic.nsf");
  nsf::TrainOptions o = tiny_options();
  o.base_model = model();
  nsf::testing::expect_contains(
      nsf::testing::error_of([&] { nsf::train_model(other.string(), out, o); }),
      "trained for scene 'synthetic'");
  std::string log;
  const std::string cmd = "train '" + data() + "' --out '" + out + "' -j 1 -q ";
  EXPECT_NE(nsf::testing::run_cli(cmd + "--base-model '" + model() + "' --width-h 8", log), 0);
  EXPECT_NE(log.find("fixes the networks' shapes"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(out));
}
