#pragma once
// The options every `nsf` command spells alike (README, "Command-line conventions"):
// -j/--threads N, threads, 0 = all cores; -q/--quiet, no progress lines. Results and errors
// print either way.
#include <CLI/CLI.hpp>
#include <string>

#include "app/option_checks.h"

namespace nsf::app {

// -j/--threads: `help` says what the threads run ("OpenMP threads"); the default, 0, is all cores
// unless `zero` says otherwise.
inline CLI::Option* add_threads_option(CLI::App* cmd, int& threads,
                                       const std::string& help = "Threads",
                                       const std::string& zero = "all cores") {
  return cmd->add_option("--threads,-j", threads, help + " (0 = " + zero + ")")
      ->capture_default_str()
      ->check(in_range(0, 1024));
}

inline CLI::Option* add_quiet_flag(CLI::App* cmd, bool& quiet,
                                   const std::string& help = "No progress lines") {
  return cmd->add_flag("--quiet,-q", quiet, help);
}

}  // namespace nsf::app
