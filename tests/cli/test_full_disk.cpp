// A disk that fills up while `nsf simulate`, `nsf sweep` or `nsf train` writes: the command must
// stop with a message about the failed write, leave no .tmp behind, and exit normally. Before,
// simulate and sweep printed the message and then crashed (SIGSEGV) in HDF5's shutdown at exit,
// and train aborted with a torch message that never said the disk was full, leaving
// m.nsf.ckpt.tmp. The full disk is a file-size limit (RLIMIT_FSIZE, with SIGXFSZ ignored so a
// write past it fails with EFBIG). The children start with SIGXFSZ at its default action, as a
// shell's `ulimit -f` leaves it: nsf ignores the signal itself (issue #54, item 9), where before it
// died of it (exit 153) with no message and left its .tmp files.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_child.h"
#include "cli_runner.h"
#include "cli_scene_fixture.h"
#include "tiny_training.h"

namespace {

namespace fs = std::filesystem;

const std::string kTinyScene = nsf::testing::tiny_cli_scene(3);

bool mentions_write_failure(const std::string& out) {
  for (const char* part : {"disk full", "No space left", "File too large", "write failed"})
    if (out.find(part) != std::string::npos) return true;
  return false;
}

TEST(FullDisk, SimulateStopsWithAMessageAndNoCrashNoFile) {
  const fs::path dir = nsf::testing::fresh_dir("full_disk");
  std::ofstream(dir / "scene.json") << kTinyScene;
  // One frame of this scene is 729 particles x 30 doubles = 175 KB: the limits run out while the
  // static data, the first frames and the last frame are written.
  for (rlim_t limit : {rlim_t(16) << 10, rlim_t(200) << 10, rlim_t(600) << 10}) {
    SCOPED_TRACE("file size limit " + std::to_string(limit) + " bytes");
    const fs::path out = dir / "run.h5", log = dir / "log.txt";
    const pid_t pid = nsf::testing::spawn_cli(
        {"simulate", (dir / "scene.json").string(), "--out", out.string(), "-q", "-j", "1"},
        log.string(), [limit] {
          ::signal(SIGXFSZ, SIG_DFL);
          const rlimit r{limit, limit};
          ::setrlimit(RLIMIT_FSIZE, &r);
        });
    ASSERT_GT(pid, 0);
    const int status = nsf::testing::wait_child(pid);
    const std::string output = nsf::testing::read_text(log.string());
    ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << WTERMSIG(status) << ": " << output;
    EXPECT_NE(WEXITSTATUS(status), 0) << output;
    EXPECT_TRUE(mentions_write_failure(output)) << output;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(out.string() + ".tmp"));
  }
  fs::remove_all(dir);
}

// Runs nsf with `args` under a file-size limit of `limit` bytes; returns the raw wait status.
int run_under_limit(const std::vector<std::string>& args, rlim_t limit, const fs::path& log) {
  const pid_t pid = nsf::testing::spawn_cli(args, log.string(), [limit] {
    ::signal(SIGXFSZ, SIG_DFL);
    const rlimit r{limit, limit};
    ::setrlimit(RLIMIT_FSIZE, &r);
  });
  return pid > 0 ? nsf::testing::wait_child(pid) : -1;
}

// Every file under `dir` whose name ends in .tmp.
std::vector<std::string> temporaries(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.path().extension() == ".tmp") out.push_back(e.path().string());
  return out;
}

TEST(FullDisk, SweepStopsWithAMessageAndNoCrashNoTemporaries) {
  const fs::path dir = nsf::testing::fresh_dir("full_disk_sweep");
  const fs::path out = dir / "data", log = dir / "log.txt";
  const std::string scene = std::string(NSF_SOURCE_DIR) + "/scenes/examples/rom_tiny.json";
  const int status =
      run_under_limit({"sweep", scene, "--out", out.string(), "-q", "-j", "1"}, 200 << 10, log);
  const std::string output = nsf::testing::read_text(log.string());
  ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << WTERMSIG(status) << ": " << output;
  EXPECT_NE(WEXITSTATUS(status), 0) << output;
  EXPECT_TRUE(mentions_write_failure(output)) << output;
  if (fs::exists(out)) {
    EXPECT_EQ(temporaries(out), std::vector<std::string>{});
  }
  fs::remove_all(dir);
}

TEST(FullDisk, TrainStopsWithAMessageAndNoCrashNoTemporaries) {
  const fs::path dir = nsf::testing::fresh_dir("full_disk_train");
  nsf::test::write_synthetic_dataset(dir / "data", nsf::testing::kTinyParticles);
  const fs::path model = dir / "out" / "m.nsf", log = dir / "log.txt";
  fs::create_directories(model.parent_path());
  // The tiny model's g alone is 16 KiB: 8 KiB runs out at the first checkpoint or the model.
  std::vector<std::string> args = {"train", (dir / "data").string(), "--out", model.string()};
  std::istringstream flags(std::string(nsf::testing::kTinyTrainFlags) +
                           nsf::testing::kTinyBatchFlags);
  for (std::string f; flags >> f;) args.push_back(f);
  const int status = run_under_limit(args, 8 << 10, log);
  const std::string output = nsf::testing::read_text(log.string());
  ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << WTERMSIG(status) << ": " << output;
  EXPECT_NE(WEXITSTATUS(status), 0) << output;
  EXPECT_TRUE(mentions_write_failure(output)) << output;
  EXPECT_FALSE(fs::exists(model));
  EXPECT_EQ(temporaries(model.parent_path()), std::vector<std::string>{});
  fs::remove_all(dir);
}

}  // namespace
