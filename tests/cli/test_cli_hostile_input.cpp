// Hostile input, round two (issue #54 items 15 and 18): inputs without a size cap, run files that
// declare more than they hold, messages that named the wrong thing, an output path that ffmpeg
// read as a pattern, and option values that exited 1 where the conventions say 2. Each case
// must end in a message naming the problem and the documented exit status (docs/OUTPUT.md, "Bad
// input"), and never in an internal error.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "app/exit_codes.h"
#include "cli_scene_fixture.h"
#include "core/error.h"
#include "data/sweep_spec.h"
#include "error_matchers.h"
#include "synthetic_run.h"
#include "tiny_training.h"

namespace {

namespace fs = std::filesystem;
using nsf::testing::expect_contains;
using nsf::testing::quoted;
using nsf::testing::run_cli;

class HostileInput : public nsf::testing::CliSceneTest {
 protected:
  HostileInput() : CliSceneTest("hostile_input_") {}
  void SetUp() override {
    CliSceneTest::SetUp();
    nsf::testing::write_synthetic_run(run(), 3);
  }
  fs::path run() const { return dir_ / "r.h5"; }
};

// Grows every per-frame dataset of a run file to `frames` frames without writing them: the file
// stays a few kilobytes and declares petabytes.
void declare_frames(const fs::path& path, hsize_t frames) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  for (const char* name :
       {"/frames/time", "/frames/x", "/frames/v", "/frames/C", "/frames/F", "/frames/tau"}) {
    const hid_t set = H5Dopen2(file, name, H5P_DEFAULT);
    ASSERT_GE(set, 0) << name;
    const hid_t space = H5Dget_space(set);
    hsize_t dims[3] = {0, 0, 0};
    const int rank = H5Sget_simple_extent_dims(space, dims, nullptr);
    H5Sclose(space);
    ASSERT_GE(rank, 1);
    dims[0] = frames;
    ASSERT_GE(H5Dset_extent(set, dims), 0) << name;
    H5Dclose(set);
  }
  H5Fclose(file);
}

// The command fails with exit status `code` and a message holding every one of `parts`.
void expect_refused(const std::string& args, int code, std::initializer_list<std::string> parts) {
  SCOPED_TRACE(args);
  const nsf::testing::CliResult r = run_cli(args);
  EXPECT_EQ(r.exit_code, code) << r.output;
  for (const std::string& p : parts) expect_contains(r.output, p);
  EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
}

// Item 15: `nsf simulate /dev/zero` read 2.2 GB and died of std::bad_alloc (exit 3).
TEST_F(HostileInput, ScenesAreCappedAndDevicesRefused) {
  const std::string out = " --out " + quoted(dir_ / "o.h5") + " -q";
  expect_refused("simulate /dev/zero" + out, nsf::app::kExitError,
                 {"scene file '/dev/zero' is not a regular file"});
  // A file over the cap: read up to the cap, then refused, never parsed.
  const fs::path big = dir_ / "big.json";
  {
    std::ofstream f(big);
    f << nsf::testing::tiny_cli_scene();
  }
  fs::resize_file(big, (std::uintmax_t(64) << 20) + 1);
  expect_refused("simulate " + quoted(big) + out, nsf::app::kExitError,
                 {"scene file '" + big.string() + "' is larger than 64 MiB"});
  EXPECT_FALSE(fs::exists(dir_ / "o.h5"));
  // Exactly at the cap it is read, and runs.
  {
    std::ofstream f(big, std::ios::trunc);
    const std::string tiny = nsf::testing::tiny_cli_scene();
    f << tiny << std::string((std::size_t(64) << 20) - tiny.size(), ' ');
  }
  ASSERT_EQ(fs::file_size(big), std::uintmax_t(64) << 20);
  const nsf::testing::CliResult at_cap = run_cli("simulate " + quoted(big) + out);
  EXPECT_EQ(at_cap.exit_code, 0) << at_cap.output;
  fs::remove(dir_ / "o.h5");
  // A manifest is capped alike.
  nsf::test::write_synthetic_dataset(dir_ / "data", nsf::testing::kTinyParticles);
  fs::resize_file(dir_ / "data" / "manifest.json", (std::uintmax_t(64) << 20) + 1);
  expect_refused("train " + quoted(dir_ / "data") + " --out " + quoted(dir_ / "m.nsf") +
                     nsf::testing::kTinyTrainFlags,
                 nsf::app::kExitError, {"manifest.json' is larger than 64 MiB"});
}

// Item 15: a run file declaring 2^40 frames made render, export, contact-sheet, train and eval die
// of std::bad_alloc naming no file.
TEST_F(HostileInput, RunFilesDeclaringMoreThanTheyHoldAreRefusedBeforeAllocating) {
  declare_frames(run(), hsize_t(1) << 40);
  ASSERT_LT(fs::file_size(run()), std::uintmax_t(1) << 20);
  const std::string r = quoted(run()), o = quoted(dir_ / "out");
  for (const std::string& args :
       {"render " + r + " --out " + o + " --no-video -q", "export " + r + " --out " + o + " -q",
        "contact-sheet " + r + " --out " + quoted(dir_ / "sheet.png")})
    expect_refused(args, nsf::app::kExitError,
                   {run().string() + ": dataset /frames/time declares 1099511627776 values",
                    "the file holds"});
  EXPECT_FALSE(fs::exists(dir_ / "out"));
  EXPECT_FALSE(fs::exists(dir_ / "sheet.png"));

  // In a dataset: the same for train and eval (with a model of the intact dataset), naming the run.
  const fs::path data = dir_ / "data";
  nsf::test::write_synthetic_dataset(data, nsf::testing::kTinyParticles);
  const nsf::testing::CliResult trained = nsf::testing::train_tiny(data, dir_ / "good.nsf");
  ASSERT_EQ(trained.exit_code, 0) << trained.output;
  declare_frames(data / "train_1.h5", hsize_t(1) << 40);
  declare_frames(data / "test_0.h5", hsize_t(1) << 40);
  const std::string named = ": dataset /frames/time declares 1099511627776 values";
  expect_refused("train " + quoted(data) + " --out " + quoted(dir_ / "m.nsf") +
                     nsf::testing::kTinyTrainFlags + nsf::testing::kTinyBatchFlags,
                 nsf::app::kExitError, {(data / "train_1.h5").string() + named});
  EXPECT_FALSE(fs::exists(dir_ / "m.nsf"));
  EXPECT_FALSE(fs::exists(dir_ / "m.nsf.ckpt"));
  expect_refused("eval " + quoted(dir_ / "good.nsf") + " " + quoted(data) + " -j 1",
                 nsf::app::kExitError, {(data / "train_1.h5").string() + named});
}

// Item 18: messages that named the wrong problem, or none.
TEST_F(HostileInput, MessagesNameTheProblem) {
  // A model path that exists but is a device: not "does not exist".
  expect_refused("rom /dev/zero " + quoted(scene()) + " --out " + quoted(dir_ / "o.h5"),
                 nsf::app::kExitError, {"model file /dev/zero is not a regular file"});
  // A camera 1e300 m away: out of range, not "up is parallel to the view direction".
  expect_refused("render " + quoted(run()) + " --out " + quoted(dir_ / "f") +
                     " --no-video -q --camera 'eye=1e300,0,0 target=0,0,0'",
                 nsf::app::kExitUsage, {"--camera: eye=1e300,0,0 is out of range"});
  std::string far = nsf::testing::tiny_cli_scene();
  far.insert(far.rfind('}'), R"(, "camera": {"eye": [1e300, 0, 0], "target": [0, 0, 0]})");
  std::ofstream(dir_ / "far.json") << far;
  expect_refused("simulate " + quoted(dir_ / "far.json") + " --out " + quoted(dir_ / "o.h5"),
                 nsf::app::kExitError, {"'camera.eye'", "is out of range"});
  // The XDMF file simulate writes beside --out, given as the scene: name the scene argument.
  std::ofstream(dir_ / "o.xdmf") << "<Xdmf/>";
  expect_refused("simulate " + quoted(dir_ / "o.xdmf") + " --out " + quoted(dir_ / "o.h5"),
                 nsf::app::kExitError,
                 {"the scene argument '" + (dir_ / "o.xdmf").string() + "'",
                  "the XDMF file nsf simulate writes beside --out '" + (dir_ / "o.h5").string()});
  EXPECT_EQ(nsf::testing::file_bytes(dir_ / "o.xdmf"), "<Xdmf/>");
  // mu = NaN through a sweep: said so, not "'objects[0].velocity[0]' must be a number".
  const nlohmann::json s = nlohmann::json::parse(R"({"objects": [{"velocity": [1, 0, 0]}],
      "sweep": {"parameter": "speed", "set": ["objects[0].velocity=[{mu},0,0]"],
                "range": [0.5, 1.5], "train": 2, "test": 1}})");
  const nsf::SweepSpec spec = nsf::parse_sweep(s.at("sweep"), s);
  for (double mu : {std::nan(""), std::numeric_limits<double>::infinity()})
    nsf::testing::expect_error([&] { nsf::sweep_overrides(spec, mu); },
                               {"mu must be a finite number", "'speed'"});
}

// Item 18: an output directory holding '%' reached ffmpeg as part of its frame pattern, which
// then found no frames.
TEST_F(HostileInput, AnOutputPathWithPercentSignsMakesItsVideo) {
  if (!nsf::testing::ffmpeg_available()) GTEST_SKIP() << "no ffmpeg on this machine";
  const fs::path out = dir_ / "100%d %s%%";
  const nsf::testing::CliResult r =
      run_cli("render " + quoted(run()) + " --out " + quoted(out) + " --size 64x48 -q -j 1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(out / "r.mp4") || fs::exists(out / "r.gif")) << r.output;
}

// Item 18: every malformed option value of render, export, contact-sheet and calibrate (and a --set
// without '=' anywhere) is a usage error (exit 2, "nsf: usage error: ", naming the option); some
// exited 1, one exited 0.
TEST_F(HostileInput, MalformedOptionValuesAreUsageErrors) {
  const std::string r = quoted(run());
  const std::string render = "render " + r + " --out " + quoted(dir_ / "f") + " --no-video -q ";
  const std::string exp = "export " + r + " --out " + quoted(dir_ / "e") + " -q ";
  const std::string sheet = "contact-sheet " + r + " --out " + quoted(dir_ / "c.png") + " ";
  const std::string cal = "calibrate " + quoted(dir_ / "m.nsf") + " " + quoted(dir_) + " ";
  struct Case {
    std::string args, option;
  };
  std::vector<Case> cases;
  for (const char* size : {"10x", "abc", "", "0x0", "100000x100000", "10x10x", "-1x5"}) {
    cases.push_back({render + "--size '" + size + "'", "--size"});
    cases.push_back({sheet + "--size '" + size + "'", "--size"});
  }
  for (const char* range : {"abc", "5:1", "nan:1", "1:inf", "1"})
    cases.push_back({render + "--range '" + range + "'", "--range"});
  for (const char* camera : {"abc", "eye=1,2", "eye=0,0,0 target=0,0,0", "eye=0,1,0 target=0,0,0",
                             "eye=1,1,1", "eye=1,1,1 target=0,0,0 fov=200"})
    cases.push_back({render + "--camera '" + camera + "'", "--camera"});
  for (const char* frames : {"abc", "1:2:0", "5:1", "100", "-100:", "0:1:2:3", "1.5"}) {
    cases.push_back({render + "--frames '" + frames + "'", "--frames"});
    cases.push_back({exp + "--frames '" + frames + "'", "--frames"});
  }
  cases.push_back({cal + "--dt-tolerance nan", "--dt-tolerance"});
  cases.push_back({cal + "--dt-budget nan", "--dt-budget"});
  cases.push_back({cal + "--dt-ratios 2,1", "--dt-ratios"});
  cases.push_back({cal + "--set abc", "--set"});
  cases.push_back(
      {"simulate " + quoted(scene()) + " --out " + quoted(dir_ / "o.h5") + " --set =1", "--set"});
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    const nsf::testing::CliResult res = run_cli(c.args);
    EXPECT_EQ(res.exit_code, nsf::app::kExitUsage) << res.output;
    expect_contains(res.output, "nsf: usage error: ");
    expect_contains(res.output, c.option);
  }
  EXPECT_FALSE(fs::exists(dir_ / "f"));
  EXPECT_FALSE(fs::exists(dir_ / "e"));
  EXPECT_FALSE(fs::exists(dir_ / "c.png"));
  EXPECT_FALSE(fs::exists(dir_ / "o.h5"));
}

}  // namespace
