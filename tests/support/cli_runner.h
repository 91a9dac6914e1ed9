#pragma once
// Runs the `nsf` executable from tests and captures its exit code and combined output.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace nsf::testing {

// Runs the nsf executable with `args` (after `env`, e.g. "PATH=/nonexistent"); returns its exit
// code and its stdout + stderr in `output`.
inline int run_cli(const std::string& args, std::string& output, const std::string& env = "") {
  namespace fs = std::filesystem;
  const fs::path log = fs::temp_directory_path() / ("nsf_cli_" + std::to_string(::getpid()) + "_" +
                                                    std::to_string(std::rand()) + ".log");
  const std::string cmd = env + " '" NSF_CLI "' " + args + " > '" + log.string() + "' 2>&1";
  const int status = std::system(cmd.c_str());
  std::ifstream in(log);
  std::stringstream ss;
  ss << in.rdbuf();
  output = ss.str();
  fs::remove(log);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

struct CliResult {
  int exit_code;
  std::string output;
};

inline CliResult run_cli(const std::string& args) {
  CliResult r;
  r.exit_code = run_cli(args, r.output);
  return r;
}

// A fresh, empty directory under the system temp dir.
inline std::filesystem::path fresh_dir(const std::string& name) {
  // One per process: ctest -j runs the cases of one fixture side by side, each in its own.
  auto d = std::filesystem::temp_directory_path() /
           ("nsf_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace nsf::testing
