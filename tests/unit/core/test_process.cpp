// run_program and program_exists: other programs are started without a shell, so no character in
// an argument (file and scene names come from users and datasets) is ever shell syntax.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "core/process.h"

namespace {

namespace fs = std::filesystem;
using nsf::program_exists;
using nsf::run_program;

std::string read_file(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Arguments that a shell would run `touch PWNED` for, each in `dir` and in the working directory.
std::vector<std::string> hostile_arguments(const fs::path& dir) {
  const std::string abs = (dir / "PWNED").string();
  return {"x'; system \"touch PWNED\"; #",
          "m';touch PWNED;'.nsf",
          "m';touch " + abs + ";'.nsf",
          "$(touch " + abs + ")",
          "`touch " + abs + "`",
          "a\"b'c;d|e&f>g<h\n$(touch PWNED)\ntouch " + abs + "\n",
          "; touch " + abs,
          "-rf"};
}

// Runs the test body in a fresh directory, so that a relative `touch PWNED` would land there.
class Process : public ::testing::Test {
 protected:
  void SetUp() override {
    old_ = fs::current_path();
    dir_ = nsf::testing::fresh_dir("process");
    fs::current_path(dir_);
  }
  void TearDown() override {
    fs::current_path(old_);
    fs::remove_all(dir_);
  }
  fs::path old_, dir_;
};

TEST_F(Process, ReturnsTheExitStatus) {
  EXPECT_EQ(run_program({"true"}), 0);
  EXPECT_EQ(run_program({"false"}), 1);
  EXPECT_EQ(run_program({"sh", "-c", "exit 7"}), 7);
  EXPECT_EQ(run_program({"sh", "-c", "kill -TERM $$"}), 128 + 15);
}

TEST_F(Process, ReturnsMinusOneWhenTheProgramCannotStart) {
  EXPECT_EQ(run_program({}), -1);
  EXPECT_EQ(run_program({""}), -1);
  EXPECT_EQ(run_program({"nsf-no-such-program-here"}), -1);
  EXPECT_EQ(run_program({"true"}, (dir_ / "no" / "such" / "dir" / "log").string()), -1);
}

TEST_F(Process, PassesEveryArgumentVerbatimAndRunsNothingElse) {
  for (const std::string& arg : hostile_arguments(dir_)) {
    const fs::path out = dir_ / "out.txt";
    ASSERT_EQ(run_program({"printf", "%s", arg}, out.string()), 0) << arg;
    EXPECT_EQ(read_file(out), arg);
    EXPECT_FALSE(fs::exists(dir_ / "PWNED")) << arg;
  }
  // The program name itself is not shell text either.
  for (const std::string& arg : hostile_arguments(dir_)) {
    EXPECT_EQ(run_program({arg}), -1) << arg;
    EXPECT_FALSE(program_exists(arg)) << arg;
    EXPECT_FALSE(fs::exists(dir_ / "PWNED")) << arg;
  }
}

TEST_F(Process, HostileOutputFileNamesAreJustFileNames) {
  for (const std::string& name : {std::string("log';touch PWNED;'.txt"),
                                  std::string("$(touch PWNED).log"), std::string("a\nb;c")}) {
    ASSERT_EQ(run_program({"sh", "-c", "echo out; echo err >&2"}, name), 0) << name;
    EXPECT_EQ(read_file(dir_ / name), "out\nerr\n") << "stdout and stderr both go to the file";
    EXPECT_FALSE(fs::exists(dir_ / "PWNED")) << name;
  }
}

TEST_F(Process, StdinIsEmpty) {
  // `cat` with our stdin would wait on the terminal; with /dev/null it ends at once.
  const fs::path out = dir_ / "cat.txt";
  EXPECT_EQ(run_program({"cat"}, out.string()), 0);
  EXPECT_EQ(read_file(out), "");
}

TEST_F(Process, ProgramExistsSearchesPath) {
  EXPECT_TRUE(program_exists("sh"));
  EXPECT_FALSE(program_exists("nsf-no-such-program-here"));
  EXPECT_FALSE(program_exists(""));
  const std::string sh = nsf::find_on_path("sh");
  ASSERT_FALSE(sh.empty());
  EXPECT_EQ(sh.front(), '/');
  EXPECT_TRUE(program_exists(sh)) << "a path is taken as it is";
  // A plain file is not a program.
  std::ofstream(dir_ / "not_executable") << "#!/bin/sh\n";
  EXPECT_FALSE(program_exists((dir_ / "not_executable").string()));
}

}  // namespace
