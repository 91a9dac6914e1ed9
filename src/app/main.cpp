// The `nsf` command-line tool: thin subcommands over libnsf.
#include <omp.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <csignal>
#include <fstream>
#include <iostream>

#include "app/cli_help.h"
#include "app/commands.h"
#include "app/exit_codes.h"
#include "core/error.h"

namespace nsf::app {

int set_threads(int requested) {
  if (requested > 0) omp_set_num_threads(requested);
  const int threads = omp_get_max_threads();
  // Fork-join parallelism waits for every thread at each barrier; on a machine already busy
  // with other work that costs far more than a second thread gains (measured: up to 10x slower).
  double load = 0;
  std::ifstream("/proc/loadavg") >> load;
  const int cores = omp_get_num_procs();
  if (threads > 1 && load > cores - 0.5)
    std::cerr << "nsf: note: the machine is busy (load average " << load << " on " << cores
              << " cores); with " << threads << " threads each step waits for the slowest, so "
              << "--threads 1 or OMP_WAIT_POLICY=passive in the environment may be faster.\n";
  return threads;
}

namespace {

// Every command, each with the exit statuses in its help.
void add_commands(CLI::App& app) {
  add_simulate_command(app);
  add_nn_commands(app);
  add_sweep_command(app);
  add_render_command(app);
  add_export_command(app);
  add_contact_sheet_command(app);
  add_rom_command(app);
  add_calibrate_command(app);
  add_demo_command(app);
  add_report_command(app);
  add_serve_command(app);
  add_generalize_command(app);
  add_upgrade_command(app);
  add_self_description_commands(app);
  for (CLI::App* cmd : app.get_subcommands({}))
    cmd->footer("Exit status: 0 success, 1 error, 2 usage error, 3 internal error (nsf --help).");
}

// A mistyped command gets a suggestion, not CLI11's "A subcommand is required", and an unknown
// option of a known command its own message; returns the usage status for either, else 0.
int refuse_unknown_names(CLI::App& app, int argc, char** argv) {
  if (argc > 1 && argv[1][0] != '-') {
    std::vector<std::string> names;
    for (const CLI::App* c : app.get_subcommands({})) names.push_back(c->get_name());
    if (std::find(names.begin(), names.end(), argv[1]) == names.end()) {
      const std::string near = nearest_name(argv[1], names);
      std::cerr << "nsf: usage error: '" << argv[1] << "' is not an nsf command"
                << (near.empty() ? "" : "; did you mean '" + near + "'?")
                << "\nRun with --help for more information.\n";
      return kExitUsage;
    }
    const std::string unknown = unknown_option(*app.get_subcommand(argv[1]),
                                               std::vector<std::string>(argv + 2, argv + argc));
    if (!unknown.empty()) {
      std::cerr << "nsf: usage error: " << unknown << "\nRun with --help for more information.\n";
      return kExitUsage;
    }
  }
  return 0;
}

}  // namespace

}  // namespace nsf::app

int main(int argc, char** argv) {
  using namespace nsf::app;
  // A file-size limit (`ulimit -f`) then makes a write fail with EFBIG, which every writer reports
  // like a full disk and cleans up after, instead of killing the process mid-file (SIGXFSZ).
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{"nsf: neural stress fields for reduced-order elastoplasticity and fracture"};
  app.require_subcommand(1);
  app.set_version_flag("--version", version_text());
  app.footer(exit_status_help());
  // Usage errors say so, like the runtime errors' "nsf: error: ".
  app.failure_message([](const CLI::App* a, const CLI::Error& e) {
    return "nsf: usage error: " + CLI::FailureMessage::simple(a, e);
  });
  add_commands(app);
  if (const int status = refuse_unknown_names(app, argc, argv)) return status;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version (CLI11's status 0) print and succeed; every other parse error is a
    // usage error, whatever CLI11's own number for it (105, 106, 109, ...).
    return app.exit(e) == 0 ? kExitSuccess : kExitUsage;
  } catch (const nsf::Error& e) {
    std::cerr << "\nnsf: error: " << e.what() << "\n";
    return kExitError;
  } catch (const std::exception& e) {
    std::cerr << "\nnsf: internal error: " << e.what() << "\n";
    return kExitInternal;
  }
  return kExitSuccess;
}
