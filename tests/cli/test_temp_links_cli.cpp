// Issue #54, items 4 and 6, for the commands: `nsf simulate` and `nsf train` refuse a symbolic
// link planted at their outputs' temporary names (temp_links_fixture.h), and a dataset's manifest
// cannot make nsf open files outside the dataset. Each case: a clear error naming the link (or the
// file), a non-zero exit, and the link's target untouched.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "error_matchers.h"
#include "nn_fixtures.h"
#include "temp_links_fixture.h"
#include "tiny_training.h"

namespace {

namespace fs = std::filesystem;
using nsf::testing::expect_contains;
using nsf::testing::quoted;
using nsf::testing::run_cli;
using nsf::testing::temp_links::TempLinks;

// A one-frame scene for `nsf simulate`.
void write_tiny_scene(const fs::path& scene) {
  std::ofstream(scene) << R"({"name": "tiny",
    "simulation": {"domain_lo": [0,0,0], "domain_hi": [0.5,0.5,0.5], "dx": 0.03125, "dt": 5e-4,
                   "frames": 1, "substeps": 2},
    "objects": [{"shape": {"type": "box", "min": [0.15,0.15,0.15], "max": [0.3,0.3,0.3]},
                 "material": {"type": "fixed_corotated", "E": 1e4, "nu": 0.3}}]})";
}

TEST_F(TempLinks, SimulateRefusesALinkAtTheRunsTempName) {
  const fs::path scene = dir_ / "scene.json", out = dir_ / "o.h5";
  write_tiny_scene(scene);
  plant(dir_ / "o.h5.tmp");
  const auto r = run_cli("simulate " + quoted(scene) + " -q -j 1 --out " + quoted(out));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  expect_contains(r.output, "o.h5.tmp");
  expect_refused(r.output, out);
  EXPECT_FALSE(fs::exists(out));
  // With the link gone, the same command writes the run.
  fs::remove(dir_ / "o.h5.tmp");
  EXPECT_EQ(run_cli("simulate " + quoted(scene) + " -q -j 1 --out " + quoted(out)).exit_code, 0);
  EXPECT_TRUE(fs::is_regular_file(out));
  expect_victim_untouched();
}

// `--out` naming a pipe (or, as root, /dev/null): refused before the run, the pipe left a pipe.
TEST_F(TempLinks, SimulateRefusesAnOutputThatIsNotARegularFile) {
  const fs::path scene = dir_ / "scene.json", out = dir_ / "o.h5";
  write_tiny_scene(scene);
  ASSERT_EQ(::mkfifo(out.c_str(), 0600), 0);
  const auto r = run_cli("simulate " + quoted(scene) + " -q -j 1 --out " + quoted(out));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  expect_contains(r.output, out.string() + " is not a regular file");
  EXPECT_TRUE(fs::is_fifo(out));
  EXPECT_FALSE(fs::exists(dir_ / "o.h5.tmp"));
  EXPECT_FALSE(fs::exists(dir_ / "o.xdmf"));
}

TEST_F(TempLinks, TrainRefusesLinksAtTheModelsAndCheckpointsTempNames) {
  const fs::path data = dir_ / "data", model = dir_ / "m.nsf";
  nsf::test::write_synthetic_dataset(data, nsf::testing::kTinyParticles);
  for (const char* tmp : {"m.nsf.tmp", "m.nsf.ckpt.tmp"}) {
    SCOPED_TRACE(tmp);
    plant(dir_ / tmp);
    const auto r = nsf::testing::train_tiny(data, model, "--fresh");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    expect_contains(r.output, tmp);
    expect_refused(r.output, model);
    fs::remove(dir_ / tmp);
    fs::remove(dir_ / "m.nsf.ckpt");
  }
  // The loss picture is a note, not the result: a link there costs the picture, never the model,
  // and never the victim.
  plant(dir_ / "m.loss.png.tmp");
  const auto r = nsf::testing::train_tiny(data, model, "--fresh");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::is_regular_file(model));
  expect_victim_untouched();
}

TEST_F(TempLinks, AManifestCannotReachOutsideTheDataset) {
  const fs::path data = dir_ / "data";
  nsf::test::write_synthetic_dataset(data, nsf::testing::kTinyParticles);
  fs::copy_file(data / "train_0.h5", dir_ / "outside.h5");
  for (const std::string& entry :
       std::vector<std::string>{"../outside.h5", (dir_ / "outside.h5").string(), "/etc/passwd",
                                "sub/../../outside.h5"}) {
    SCOPED_TRACE(entry);
    std::ofstream(data / "manifest.json")
        << R"({"train": ["train_0.h5", ")" << entry << R"("], "test": ["test_0.h5"]})";
    const auto r = nsf::testing::train_tiny(data, dir_ / "m.nsf");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    expect_contains(r.output, "is outside the dataset directory");
    expect_contains(r.output, entry);
  }
}

}  // namespace
