// Interrupted commands: Ctrl-C (SIGINT), SIGTERM or SIGHUP while `nsf simulate` writes its run must
// not leave <out>.tmp behind (before, 16-43 MB of it per interrupted run), and the process must
// still die of the signal. The temp-file registry itself is checked in a forked child.
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "cli_child.h"
#include "cli_runner.h"
#include "core/temp_files.h"

namespace {

namespace fs = std::filesystem;

// Thousands of frames: minutes of work, so it is always mid-run when the signal comes.
const char* kLongScene = R"({
  "name": "long",
  "simulation": {"domain_lo": [0,0,0], "domain_hi": [0.5,0.5,0.5], "dx": 0.03125, "dt": 5e-4,
                 "frames": 100000, "substeps": 4},
  "objects": [{"shape": {"type": "box", "min": [0.15,0.15,0.15], "max": [0.3,0.3,0.3]},
               "material": {"type": "fixed_corotated", "E": 1e4, "nu": 0.3}}]
})";

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
