// Issue #54, items 4 and 6: the temporary name every output is written under ("<out>.tmp") is
// created exclusively, never through a symbolic link planted there, and a dataset's manifest
// cannot make nsf open files outside the dataset. Each case: a clear error naming the link (or the
// file), a non-zero exit, and the link's target untouched.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "core/error.h"
#include "core/exclusive_file.h"
#include "data/manifest.h"
#include "error_matchers.h"
#include "io/atomic_file.h"
#include "io/image.h"
#include "tiny_training.h"

namespace {

namespace fs = std::filesystem;
using nsf::testing::expect_contains;
using nsf::testing::file_bytes;
using nsf::testing::quoted;
using nsf::testing::run_cli;

constexpr const char* kVictimText = "the victim's own contents\n";

class TempLinks : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = nsf::testing::fresh_dir(std::string("temp_links_") +
                                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::ofstream(victim()) << kVictimText;
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path victim() const { return dir_ / "victim.txt"; }
  // A link at `tmp` to the victim, as an attacker with write access to the output folder (or a
  // shared /tmp) would plant it.
  void plant(const fs::path& tmp) const { fs::create_symlink(victim(), tmp); }
  void expect_victim_untouched() const { EXPECT_EQ(file_bytes(victim()), kVictimText); }
  // The refusal names the link; the final name was not made into a link to the victim.
  void expect_refused(const std::string& message, const fs::path& out) const {
    expect_contains(message, "symbolic link");
    expect_victim_untouched();
    EXPECT_FALSE(fs::is_symlink(out)) << out;
  }
  fs::path dir_;
};

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const nsf::Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error";
  return "";
}

TEST_F(TempLinks, AtomicFileRefusesALinkAtItsTempName) {
  const fs::path out = dir_ / "row.json";
  plant(dir_ / "row.json.tmp");
  expect_refused(error_of([&] { nsf::write_file_atomic(out.string(), "{}"); }), out);
  EXPECT_TRUE(fs::is_symlink(dir_ / "row.json.tmp")) << "the planted link is left alone";
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(TempLinks, AStaleTempFileIsReplacedNotWrittenThrough) {
  // A killed run's leftover is a regular file: removed, then the temp file is created afresh. A
  // hard link to the victim is such a file too, and unlinking it leaves the victim as it was.
  const fs::path out = dir_ / "row.json";
  fs::create_hard_link(victim(), dir_ / "row.json.tmp");
  nsf::write_file_atomic(out.string(), "{}\n");
  EXPECT_EQ(file_bytes(out), "{}\n");
  EXPECT_FALSE(fs::exists(dir_ / "row.json.tmp"));
  expect_victim_untouched();
}

TEST_F(TempLinks, ADirectoryAtTheTempNameIsRefused) {
  fs::create_directory(dir_ / "row.json.tmp");
  expect_contains(error_of([&] { nsf::write_file_atomic((dir_ / "row.json").string(), "{}"); }),
                  "not a regular file");
  EXPECT_TRUE(fs::is_directory(dir_ / "row.json.tmp"));
}

TEST_F(TempLinks, PngAndManifestWritersRefuseALink) {
  const fs::path png = dir_ / "a.png", manifest = dir_ / "manifest.json";
  plant(dir_ / "a.png.tmp");
  plant(dir_ / "manifest.json.tmp");
  expect_refused(error_of([&] { nsf::write_png(nsf::Image(4, 4, {1, 2, 3}), png.string()); }), png);
  expect_refused(
      error_of([&] { nsf::write_json_atomically(manifest.string(), nlohmann::json::object()); }),
      manifest);
}

TEST_F(TempLinks, SimulateRefusesALinkAtTheRunsTempName) {
  const fs::path scene = dir_ / "scene.json", out = dir_ / "o.h5";
  std::ofstream(scene) << R"({"name": "tiny",
    "simulation": {"domain_lo": [0,0,0], "domain_hi": [0.5,0.5,0.5], "dx": 0.03125, "dt": 5e-4,
                   "frames": 1, "substeps": 2},
    "objects": [{"shape": {"type": "box", "min": [0.15,0.15,0.15], "max": [0.3,0.3,0.3]},
                 "material": {"type": "fixed_corotated", "E": 1e4, "nu": 0.3}}]})";
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
