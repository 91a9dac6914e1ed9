// `nsf train --device` and `--json` (docs/TRAINING.md, "Training on a GPU"). Where this build's
// LibTorch has CUDA and a device is visible, a run on it must reach the CPU run's losses; where
// not (Debian's LibTorch, CI), --device cuda must stop before reading anything, with a message
// that says why and where to look.
#include <gtest/gtest.h>
#include <torch/cuda.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_child.h"
#include "error_matchers.h"
#include "tiny_training.h"

namespace {

namespace fs = std::filesystem;
using nsf::testing::expect_contains;
using nsf::testing::quoted;
using nsf::testing::train_tiny;

class TrainDevice : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = nsf::testing::fresh_dir(std::string("train_device_") +
                                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
    nsf::test::write_synthetic_dataset(data(), nsf::testing::kTinyParticles);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path data() const { return dir_ / "data"; }
  fs::path dir_;
};

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

TEST_F(TrainDevice, JsonRowHoldsEachStagesStepsAndTime) {
  const fs::path json = dir_ / "row.json";
  const nsf::testing::CliResult r =
      train_tiny(data(), dir_ / "m.nsf", "--device cpu --json " + quoted(json));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json row = read_json(json);
  EXPECT_EQ(row.at("device"), "cpu");
  EXPECT_EQ(row.at("threads"), 1);
  ASSERT_EQ(row.at("stages").size(), 3u);
  // kTinyTrainFlags; stage 3's C is a coefficient map, fitted, not stepped.
  const long steps[3] = {20, 5, 0};
  for (int s = 0; s < 3; ++s) {
    const nlohmann::json& st = row.at("stages")[size_t(s)];
    EXPECT_EQ(st.at("stage"), s + 1);
    EXPECT_EQ(st.at("steps").get<long>(), steps[s]);
    EXPECT_EQ(st.at("fitted").get<bool>(), s == 2);
    EXPECT_GT(st.at("seconds").get<double>(), 0);
    if (s < 2) {
      EXPECT_GT(st.at("points_per_second").get<double>(), 0);
    }
    EXPECT_TRUE(std::isfinite(st.at("final_loss").get<double>()));
  }
  EXPECT_FALSE(fs::exists(json.string() + ".tmp"));
}

TEST_F(TrainDevice, JsonOnTheModelsPathIsRefused) {
  const fs::path model = dir_ / "m.nsf";
  const nsf::testing::CliResult r = train_tiny(data(), model, "--json " + quoted(model));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  expect_contains(r.output, "--json");
  EXPECT_FALSE(fs::exists(model));
}

TEST_F(TrainDevice, AnUnknownDeviceIsRefusedBeforeReading) {
  const fs::path model = dir_ / "m.nsf";
  const nsf::testing::CliResult r = train_tiny(data(), model, "--device gpu0");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  expect_contains(r.output, "--device gpu0: not a device (cpu, cuda or cuda:N)");
  EXPECT_EQ(r.output.find("nsf train: "), std::string::npos) << "the dataset was read first";
  EXPECT_FALSE(fs::exists(model));
}

TEST_F(TrainDevice, CudaTrainsToTheCpusLossesOrSaysWhyNot) {
  const fs::path cpu_json = dir_ / "cpu.json", cuda_json = dir_ / "cuda.json";
  const fs::path cuda_model = dir_ / "cuda.nsf";
  const nsf::testing::CliResult cuda =
      train_tiny(data(), cuda_model, "--device cuda --json " + quoted(cuda_json));
  if (!torch::cuda::is_available()) {
    EXPECT_EQ(cuda.exit_code, 1) << cuda.output;
    expect_contains(cuda.output, "--device cuda: this nsf was built with a LibTorch without CUDA");
    expect_contains(cuda.output, "Training on a GPU");
    EXPECT_FALSE(fs::exists(cuda_model));
    return;
  }
  ASSERT_EQ(cuda.exit_code, 0) << cuda.output;
  const nsf::testing::CliResult cpu =
      train_tiny(data(), dir_ / "cpu.nsf", "--device cpu --json " + quoted(cpu_json));
  ASSERT_EQ(cpu.exit_code, 0) << cpu.output;
  // Same seed, same batches drawn on the host: the losses differ by float rounding only.
  const nlohmann::json a = read_json(cpu_json), b = read_json(cuda_json);
  for (size_t s = 0; s < 3; ++s) {
    const double la = a["stages"][s]["final_loss"], lb = b["stages"][s]["final_loss"];
    EXPECT_NEAR(lb, la, 1e-3 * std::abs(la)) << "stage " << s + 1;
  }
  // The model file holds CPU tensors: it loads and evaluates where there is no GPU.
  const nsf::testing::CliResult eval =
      nsf::testing::run_cli("eval " + quoted(cuda_model) + " " + quoted(data()));
  EXPECT_EQ(eval.exit_code, 0) << eval.output;
}

}  // namespace
