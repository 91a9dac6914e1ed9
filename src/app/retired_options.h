#pragma once
// Options of experiments that lost and were removed from nsf (docs/experiments/README.md). Each
// still parses, only to refuse with a usage error that names the record of what it gave, so that
// an old command line says why it no longer runs instead of "unknown option".
#include <CLI/CLI.hpp>
#include <string>

namespace nsf::app {

// Registers on `cmd`, the subcommand named `command`, its retired options as hidden options
// that fail with "nsf: usage error: --FLAG was retired (it lost: docs/experiments/....md)".
void add_retired_options(CLI::App* cmd, const std::string& command);

// The check of a field-source option (`nsf rom --deformation`, `--stress`, `--affine`) for the
// role it names: a retired source's name is a usage error naming its record (before CLI11's
// list of the registered names refuses it without one).
CLI::Validator not_a_retired_source(const std::string& role);

}  // namespace nsf::app
