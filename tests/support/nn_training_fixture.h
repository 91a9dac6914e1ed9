#pragma once
// A small MLP model trained once per test process (SetUpTestSuite) on the synthetic dataset of
// nn_fixtures.h, and the loss curve training writes: the fixture of NnTraining, whose tests are
// unit/nn/test_nn_training.cpp's and cli/test_nn_training_cli.cpp's (`nsf train`).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "nn/torch_settings.h"
#include "nn/train/trainer.h"
#include "nn_fixtures.h"

namespace nsf::testing::nn_training {

namespace fs = std::filesystem;

inline constexpr int kParticles = 300;

inline nsf::TrainOptions tiny_options() {
  nsf::TrainOptions o;
  nsf::TrainConfig& c = o.config;
  c.net.decoder = nsf::DecoderFamily::mlp;
  c.net.latent_dim = 2;
  c.net.depth = 3;
  c.net.width_g = c.net.width_h = c.net.width_l = 32;
  c.net.encoder_hidden = 16;
  c.steps = {300, 200, 200};
  c.frames_per_batch = {4, 8, 8};
  c.particles_per_frame = {64, 64, 64};
  c.checkpoint_every = 50;
  c.seed = 3;
  c.quiet = true;
  return o;
}

struct LossCurve {
  std::vector<double> loss[3];
};

inline LossCurve read_losses(const std::string& csv) {
  LossCurve c;
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string stage, net, step, loss;
    std::getline(ss, stage, ',');
    std::getline(ss, net, ',');
    std::getline(ss, step, ',');
    std::getline(ss, loss, ',');
    c.loss[std::stoi(stage) - 1].push_back(std::stod(loss));
  }
  return c;
}

// One dataset and one uninterrupted training run shared by the tests (training is the slow part).
class NnTraining : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    nsf::set_nn_threads(2);
    root_ = fs::temp_directory_path() / ("nsf_nn_training_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    nsf::test::write_synthetic_dataset(root_ / "data", kParticles);
    report_ = nsf::train_model(data(), model(), tiny_options());
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }
  static std::string data() { return (root_ / "data").string(); }
  static std::string model() { return (root_ / "models" / "synthetic.nsf").string(); }
  static std::string file(const std::string& name) { return (root_ / name).string(); }

  inline static fs::path root_;
  inline static nsf::TrainReport report_;
};

}  // namespace nsf::testing::nn_training
