#pragma once
// Each subcommand of the `nsf` tool registers itself on the CLI app; one file per subcommand.
#include <CLI/CLI.hpp>

namespace nsf::app {

void add_simulate_command(CLI::App& app);
void add_nn_commands(CLI::App& app);  // train, eval (cmd_train.cpp, cmd_eval.cpp)
void add_sweep_command(CLI::App& app);
void add_render_command(CLI::App& app);
void add_export_command(CLI::App& app);
void add_contact_sheet_command(CLI::App& app);
void add_rom_command(CLI::App& app);
void add_calibrate_command(CLI::App& app);  // cmd_calibrate.cpp
void add_demo_command(CLI::App& app);
void add_report_command(CLI::App& app);
void add_serve_command(CLI::App& app);       // cmd_serve.cpp
void add_generalize_command(CLI::App& app);  // cmd_generalize.cpp
void add_upgrade_command(CLI::App& app);     // cmd_upgrade.cpp

// Sets the OpenMP thread count (0 = all cores) and returns the count in use.
int set_threads(int requested);

}  // namespace nsf::app
