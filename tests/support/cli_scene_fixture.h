#pragma once
// A fresh directory per test with the tiny scene the CLI tests run (2 frames, milliseconds), for
// the test files that check what `nsf` does with paths, ranges and hostile input.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_runner.h"

namespace nsf::testing {

// The tiny scene: a small elastic box, `frames` frames of 4 steps each (milliseconds a frame).
inline std::string tiny_cli_scene(int frames = 2) {
  return R"({
  "name": "tiny",
  "simulation": {"domain_lo": [0,0,0], "domain_hi": [0.5,0.5,0.5], "dx": 0.03125, "dt": 5e-4,
                 "frames": )" +
         std::to_string(frames) + R"(, "substeps": 4},
  "objects": [{"shape": {"type": "box", "min": [0.15,0.15,0.15], "max": [0.3,0.3,0.3]},
               "material": {"type": "fixed_corotated", "E": 1e4, "nu": 0.3}}]
})";
}

// dir_ is <tmp>/nsf_test_<prefix><test name>_<pid>, holding the tiny scene as scene().
class CliSceneTest : public ::testing::Test {
 protected:
  explicit CliSceneTest(std::string prefix) : prefix_(std::move(prefix)) {}
  void SetUp() override {
    dir_ = fresh_dir(prefix_ + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::ofstream(scene()) << tiny_cli_scene();
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path scene() const { return dir_ / "s.json"; }
  std::filesystem::path dir_;

 private:
  std::string prefix_;
};

}  // namespace nsf::testing
