// Command lines that used to destroy an input or run with a meaningless value, exit 0 (issue #28,
// items 10 and 11): an output path naming an input or another output, and numeric options out of
// range or NaN. Each must stop with a message naming the option and leave every file alone.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "app/exit_codes.h"
#include "cli_scene_fixture.h"
#include "error_matchers.h"
#include "tiny_training.h"

namespace {

namespace fs = std::filesystem;
using nsf::testing::expect_contains;
using nsf::testing::file_bytes;
using nsf::testing::quoted;
using nsf::testing::run_cli;

class PathsAndRanges : public nsf::testing::CliSceneTest {
 protected:
  PathsAndRanges() : CliSceneTest("paths_ranges_") {}
  void SetUp() override {
    CliSceneTest::SetUp();
    std::ofstream(model()) << "a model file (its content does not matter here)";
  }
  fs::path model() const { return dir_ / "m.nsf"; }
};

// The command fails, names the clash, and leaves `kept` as it was.
void expect_refused(const std::string& args, const fs::path& kept, const std::string& message) {
  SCOPED_TRACE(args);
  const std::string before = file_bytes(kept);
  const nsf::testing::CliResult r = run_cli(args);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  expect_contains(r.output, message);
  EXPECT_EQ(file_bytes(kept), before) << kept << " was changed";
}

// Item 10: an output path equal to an input path (as a file: through "..", symlinks, hard
// links) is a named error; it used to replace the input with exit 0.
TEST_F(PathsAndRanges, AnOutputNamingAnInputIsRefused) {
  const std::string s = quoted(scene()), m = quoted(model());
  expect_refused("simulate " + s + " --out " + s + " -q", scene(),
                 "--out '" + scene().string() + "' is the same file as the scene");
  // The same file by another spelling, through a symlink and a hard link.
  const fs::path sub = dir_ / "sub";
  fs::create_directories(sub);
  expect_refused("simulate " + s + " --out " + quoted(sub / ".." / "." / "s.json") + " -q", scene(),
                 "is the same file as the scene");
  fs::create_symlink(scene(), dir_ / "link.json");
  expect_refused("simulate " + quoted(dir_ / "link.json") + " --out " + s + " -q", scene(),
                 "is the same file as the scene");
  fs::create_hard_link(scene(), dir_ / "hard.json");
  expect_refused("simulate " + quoted(dir_ / "hard.json") + " --out " + s + " -q", scene(),
                 "is the same file as the scene");
  expect_refused("simulate " + s + " --out " + quoted(dir_ / "run.h5") + " --png " + s, scene(),
                 "--png");

  expect_refused("rom " + m + " " + s + " --out " + m, model(),
                 "--out '" + model().string() + "' is the same file as the model");
  expect_refused("rom " + m + " " + s + " --fom-out " + s, scene(), "--fom-out");
  // Two outputs on one file: the second would overwrite the first. Neither exists yet.
  const nsf::testing::CliResult r =
      run_cli("rom " + m + " " + s + " --out " + quoted(dir_ / "x.h5") + " --fom-out " +
              quoted(sub / ".." / "x.h5"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  expect_contains(r.output,
                  "--fom-out '" + (sub / ".." / "x.h5").string() + "' is the same file as --out");
  EXPECT_FALSE(fs::exists(dir_ / "x.h5"));

  // train: the model over one of the dataset's runs.
  nsf::test::write_synthetic_dataset(dir_ / "data", nsf::testing::kTinyParticles);
  expect_refused("train " + quoted(dir_ / "data") + " --out " +
                     quoted(dir_ / "data" / "train_0.h5") + nsf::testing::kTinyTrainFlags,
                 dir_ / "data" / "train_0.h5", "is the same file as the dataset's run");
  expect_refused("eval " + m + " " + quoted(dir_ / "data") + " --json " + m, model(), "--json");
}

struct RangeCase {
  std::string args;    // after the command
  std::string option;  // the message must name it
};

// Item 11: every numeric option has a range; NaN, infinity, zero steps, negative sizes and
// absurd values are refused with a message naming the option (they used to be accepted).
TEST_F(PathsAndRanges, NumericOptionsOutOfRangeOrNaNAreRefused) {
  const std::string train = "train " + quoted(dir_) + " --out " + quoted(dir_ / "out.nsf") + " ";
  const std::string rom = "rom " + quoted(model()) + " " + quoted(scene()) + " ";
  const std::string eval = "eval " + quoted(model()) + " " + quoted(dir_) + " ";
  const std::vector<RangeCase> cases = {
      {train + "--steps 0", "--steps"},
      {train + "--steps -5,2,2", "--steps"},
      {train + "-r 0", "--latent-dim"},
      {train + "--width-g -3", "--width-g"},
      {train + "--epochs nan", "--epochs"},
      {train + "--epochs inf", "--epochs"},
      {train + "--memory-budget -1", "--memory-budget"},
      {train + "--memory-budget nan", "--memory-budget"},
      {train + "--particles-per-frame 2e9", "--particles-per-frame"},
      {train + "--frames-per-batch 0", "--frames-per-batch"},
      {train + "--latent-noise nan", "--latent-noise"},
      {train + "--seed -1", "--seed"},
      {train + "--threads -2", "--threads"},
      {train + "--checkpoint-every -1", "--checkpoint-every"},
      {train + "--stop-after -3", "--stop-after"},
      {rom + "--gn-iterations -1", "--gn-iterations"},
      {rom + "--gn-tolerance nan", "--gn-tolerance"},
      {rom + "--dt-ratio 1e6", "--dt-ratio"},
      {rom + "--dt-ratio nan", "--dt-ratio"},
      {rom + "--mu nan", "--mu"},
      {rom + "--samples 0", "--samples"},
      {rom + "--latent-prior nan", "--latent-prior"},
      {rom + "--halo 1", "--halo"},
      {rom + "--upsample 0", "--upsample"},
      {rom + "--gzip 10", "--gzip"},
      {eval + "--every 0", "--every"},
      {"calibrate " + quoted(model()) + " " + quoted(dir_) + " --unseen --draws 0", "--draws"},
      {"calibrate " + quoted(model()) + " " + quoted(dir_) + " --seed 5", "--seed"},
      {eval + "--particles -1", "--particles"},
      {"render " + quoted(model()) + " --out " + quoted(dir_ / "r") + " --fov nan", "--fov"},
      {"demo --steps 0,1,1", "--steps"},
      {"demo --widths -1,8,8", "--widths"},
      {"sweep " + quoted(scene()) + " --out " + quoted(dir_ / "d") + " --gzip -1", "--gzip"},
      {"simulate " + quoted(scene()) + " --out " + quoted(dir_ / "r.h5") + " --gzip 10", "--gzip"},
  };
  for (const RangeCase& c : cases) {
    SCOPED_TRACE(c.args);
    const nsf::testing::CliResult r = run_cli(c.args);
    EXPECT_EQ(r.exit_code, nsf::app::kExitUsage) << r.output;
    expect_contains(r.output, c.option);
  }
  EXPECT_FALSE(fs::exists(dir_ / "out.nsf"));
}

}  // namespace
