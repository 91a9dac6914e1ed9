// Interrupted commands: Ctrl-C (SIGINT), SIGTERM or SIGHUP while `nsf simulate` writes its run must
// not leave <out>.tmp behind (before, 16-43 MB of it per interrupted run), and the process must
// still die of the signal. The temp-file registry itself is checked in a forked child.
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "cli_child.h"
#include "cli_runner.h"
#include "cli_scene_fixture.h"
#include "core/temp_files.h"

namespace {

namespace fs = std::filesystem;

// Thousands of frames: minutes of work, so it is always mid-run when the signal comes.
const std::string kLongScene = nsf::testing::tiny_cli_scene(100000);

bool wait_for(const fs::path& p, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (fs::exists(p)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

TEST(Interrupt, SignalDuringSimulateRemovesTheTempFileAndEndsByTheSignal) {
  const fs::path dir = nsf::testing::fresh_dir("interrupt");
  std::ofstream(dir / "scene.json") << kLongScene;
  for (int sig : {SIGTERM, SIGINT, SIGHUP}) {
    SCOPED_TRACE(std::string("signal ") + strsignal(sig));
    const fs::path out = dir / "run.h5", tmp = dir / "run.h5.tmp", log = dir / "log.txt";
    const pid_t pid = nsf::testing::spawn_cli(
        {"simulate", (dir / "scene.json").string(), "--out", out.string(), "-q", "-j", "1"},
        log.string());
    ASSERT_GT(pid, 0);
    const bool started = wait_for(tmp, 60);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // a few frames into the run
    ::kill(pid, started ? sig : SIGKILL);
    const int status = nsf::testing::wait_child(pid);
    ASSERT_TRUE(started) << nsf::testing::read_text(log.string());
    const bool by_signal = WIFSIGNALED(status) && WTERMSIG(status) == sig;
    const bool failed = WIFEXITED(status) && WEXITSTATUS(status) != 0;
    EXPECT_TRUE(by_signal || failed) << "status " << status;
    EXPECT_FALSE(fs::exists(tmp));
    EXPECT_FALSE(fs::exists(out));
  }
  fs::remove_all(dir);
}

// A sweep over several axes and collider paths (issue #55 item 4), killed with SIGKILL (nothing
// cleans up) after its first run: run again, it keeps the finished runs, redoes the others with
// the same values and paths, and lists every run with its values.
TEST(Interrupt, AMultiAxisSweepKilledMidwayResumesWithTheSameRuns) {
  const fs::path dir = nsf::testing::fresh_dir("interrupt_sweep");
  std::ofstream(dir / "scene.json") << R"({
    "name": "plates",
    "simulation": { "dx": 0.03125, "dt": 1e-3, "frames": 40, "substeps": 5 },
    "objects": [ { "shape": { "type": "box", "min": [0.375, 0.1, 0.375], "max": [0.625, 0.3, 0.625] },
                   "material": { "type": "fixed_corotated", "E": 1000, "nu": 0.3 } } ],
    "colliders": [
      { "type": "plane", "point": [0, 0.1, 0], "normal": [0, 1, 0], "contact": "sticky" },
      { "type": "box", "center": [0.3, 0.2, 0.5], "size": [0.05, 0.3, 0.3],
        "motion": { "keyframes": [ { "t": 0, "center": [0.3, 0.2, 0.5] },
                                   { "t": 0.1, "center": [0.36, 0.2, 0.5] } ] } } ],
    "sweep": { "parameter": "stiffness", "set": ["material.E={mu*1000}"], "range": [1, 3],
               "train": 4, "test": 1, "design": "sobol",
               "vary": [ { "name": "depth", "range": [0.34, 0.38],
                           "set": ["colliders[1].motion.keyframes[1].center=[{v},0.2,0.5]"] } ],
               "paths": [ { "name": "wander", "collider": 1, "start": 0.02, "end": 0.15,
                            "offset": [0.01, 0.02, 0.0], "max_speed": 2.0 } ] }
  })";
  const fs::path data = dir / "data", log = dir / "log.txt";
  const std::vector<std::string> args = {
      "sweep", (dir / "scene.json").string(), "--out", data.string(), "-q", "-j", "1", "--jobs",
      "1"};
  const pid_t pid = nsf::testing::spawn_cli(args, log.string());
  ASSERT_GT(pid, 0);
  const bool first_done = wait_for(data / "train_0.h5", 120);
  ::kill(pid, SIGKILL);
  nsf::testing::wait_child(pid);
  ASSERT_TRUE(first_done) << nsf::testing::read_text(log.string());
  ASSERT_FALSE(fs::exists(data / "test_0.h5")) << "the sweep finished before it was killed";
  const auto kept = fs::last_write_time(data / "train_0.h5");

  std::string out;
  std::vector<std::string> again(args.begin(), args.end());
  std::string line;
  for (const std::string& a : again) line += "'" + a + "' ";
  ASSERT_EQ(nsf::testing::run_cli(line, out), 0) << out;
  EXPECT_EQ(fs::last_write_time(data / "train_0.h5"), kept);  // not redone
  EXPECT_NE(out.find("already complete"), std::string::npos) << out;
  for (const char* f : {"train_0.h5", "train_1.h5", "train_2.h5", "train_3.h5", "test_0.h5"})
    EXPECT_TRUE(fs::exists(data / f)) << f;
  for (const auto& e : fs::directory_iterator(data))  // the killed run's temp file is gone too
    EXPECT_NE(e.path().extension(), ".tmp") << e.path();
  const nlohmann::json manifest =
      nlohmann::json::parse(nsf::testing::read_text((data / "manifest.json").string()));
  ASSERT_EQ(manifest["runs"].size(), 5u);
  EXPECT_EQ(manifest["design"], "sobol");
  for (const auto& r : manifest["runs"]) {
    EXPECT_TRUE(r["values"].contains("depth")) << r.dump();
    EXPECT_TRUE(r.contains("path_seed")) << r.dump();
  }
  // A third run redoes nothing: every file is the run its plan asks for.
  ASSERT_EQ(nsf::testing::run_cli(line, out), 0) << out;
  EXPECT_NE(out.find("0 simulated, 5 already complete"), std::string::npos) << out;
  fs::remove_all(dir);
}

TEST(Interrupt, RegisteredTempFilesAreDeletedByAFatalSignalAndReleasedOnesKept) {
  const fs::path dir = nsf::testing::fresh_dir("temp_files");
  const fs::path a = dir / "a.tmp", b = dir / "b.tmp";
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    std::ofstream(a) << "a";
    std::ofstream(b) << "b";
    nsf::TempFileRegistration ra(a.string()), rb(b.string());
    rb.release();  // b was "renamed into place": a signal must not touch it
    ::raise(SIGTERM);
    ::_exit(0);  // reached only if the signal did not end the process
  }
  const int status = nsf::testing::wait_child(pid);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << "status " << status;
  EXPECT_FALSE(fs::exists(a));
  EXPECT_TRUE(fs::exists(b));

  const int before = nsf::registered_temp_files();
  {
    nsf::TempFileRegistration r((dir / "c.tmp").string());
    EXPECT_EQ(nsf::registered_temp_files(), before + 1);
    nsf::TempFileRegistration moved = std::move(r);
    EXPECT_EQ(nsf::registered_temp_files(), before + 1);
  }
  EXPECT_EQ(nsf::registered_temp_files(), before);
  fs::remove_all(dir);
}

}  // namespace
