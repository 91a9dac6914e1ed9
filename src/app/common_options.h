#pragma once
// The options every `nsf` command spells alike (README, "Command-line conventions"):
// -j/--threads N, threads, 0 = all cores; -q/--quiet, no progress lines. Results and errors
// print either way.
#include <CLI/CLI.hpp>
#include <sstream>
#include <string>

#include "app/option_checks.h"
#include "rom/rom_options.h"

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

// --gzip LEVEL: the run files' frames deflated at LEVEL (1-9, with byte shuffling; 0 = off).
inline CLI::Option* add_gzip_option(CLI::App* cmd, int& level) {
  return cmd
      ->add_option("--gzip", level,
                   "Compress the run file's frames at this deflate level (1-9, with byte "
                   "shuffling; 0 = off): about half the disk (nsf's paper scenes: 0.3-0.65), "
                   "read as usual by nsf, h5py and ParaView")
      ->capture_default_str()
      ->check(in_range(0, 9));
}

// --profile: which settings of the scene's rom section a reduced-order run reads
// (rom/setup/rom_setup.h).
inline CLI::Option* add_profile_option(CLI::App* cmd, std::string& profile) {
  return cmd
      ->add_option("--profile", profile,
                   "Settings of the scene's rom section: auto (its rom.unseen profile for a scene "
                   "outside the model's training family, else the family's), family or unseen")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "family", "unseen"}));
}

// --guard: step through the runtime's step guard (RomEvalOptions::guard).
inline CLI::Option* add_guard_flag(CLI::App* cmd, bool& guard) {
  return cmd->add_flag("--guard", guard,
                       "Step as the runtime does, through its step guard: a step that diverges or "
                       "passes the error indicator's limits is redone and counted (default: the "
                       "bare stepper, whose divergence ends the run)");
}

// --dt-ratio: the ROM step over the scene's Δt, a number, or "cfl" for the largest step within the
// CFL bound (read as RomOptions::kDtRatioAtCfl). `help` says where the default comes from.
inline CLI::Option* add_dt_ratio_option(CLI::App* cmd, double& ratio, const std::string& help) {
  static_assert(RomOptions::kDtRatioAtCfl == 0, "\"cfl\" is read as 0 below");
  const CLI::Validator range = in_range(1e-3, 1e4);
  return cmd
      ->add_option("--dt-ratio", ratio,
                   "ROM time step over the scene's dt, or cfl: the largest step within the CFL "
                   "bound (" +
                       help + ")")
      ->transform(CLI::Validator(
          [range](std::string& input) {
            if (input != "cfl") {
              const std::string problem = range(input);
              return problem.empty() ? problem : problem + ", or cfl";
            }
            input = "0";
            return std::string();
          },
          "a number in 0.001 to 10000, or cfl"));
}

// The --dt-ratio value as a command line spells it.
inline std::string dt_ratio_arg(double ratio) {
  std::ostringstream os;
  if (ratio == RomOptions::kDtRatioAtCfl)
    os << "cfl";
  else
    os << ratio;
  return os.str();
}

inline CLI::Option* add_quiet_flag(CLI::App* cmd, bool& quiet,
                                   const std::string& help = "No progress lines") {
  return cmd->add_flag("--quiet,-q", quiet, help);
}

}  // namespace nsf::app
