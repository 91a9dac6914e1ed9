// The `nsf` command-line tool: thin subcommands over libnsf.
#include <omp.h>

#include <CLI/CLI.hpp>
#include <fstream>
#include <iostream>

#include "app/commands.h"
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

}  // namespace nsf::app

int main(int argc, char** argv) {
  CLI::App app{"nsf: neural stress fields for reduced-order elastoplasticity and fracture"};
  app.require_subcommand(1);
  app.set_version_flag("--version", NSF_VERSION);
  nsf::app::add_simulate_command(app);
  nsf::app::add_nn_commands(app);
  nsf::app::add_sweep_command(app);
  nsf::app::add_render_command(app);
  nsf::app::add_export_command(app);
  nsf::app::add_contact_sheet_command(app);
  nsf::app::add_rom_command(app);
  nsf::app::add_demo_command(app);
  nsf::app::add_report_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const nsf::Error& e) {
    std::cerr << "\nnsf: error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "\nnsf: internal error: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
