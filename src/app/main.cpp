// The `nsf` command-line tool: thin subcommands over libnsf.
#include <CLI/CLI.hpp>
#include <iostream>

#include "core/error.h"

int main(int argc, char** argv) {
  CLI::App app{"nsf: neural stress fields for reduced-order elastoplasticity"};
  app.require_subcommand(1);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const nsf::Error& e) {
    std::cerr << "nsf: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
