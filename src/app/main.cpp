// The `nsf` command-line tool: thin subcommands over libnsf.
#include <omp.h>

#include <CLI/CLI.hpp>
#include <iostream>

#include "app/commands.h"
#include "core/error.h"

namespace nsf::app {

int set_threads(int requested) {
  if (requested > 0) omp_set_num_threads(requested);
  return omp_get_max_threads();
}

}  // namespace nsf::app

int main(int argc, char** argv) {
  CLI::App app{"nsf: neural stress fields for reduced-order elastoplasticity and fracture"};
  app.require_subcommand(1);
  app.set_version_flag("--version", NSF_VERSION);
  nsf::app::add_simulate_command(app);
  nsf::app::add_render_command(app);
  nsf::app::add_export_command(app);
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
