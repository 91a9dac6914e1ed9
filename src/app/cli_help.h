#pragma once
// What the `nsf` tool says about itself: `--version` with what it was built from, a suggestion for
// a mistyped command, and the shell completion and manual page made from its own options, so that
// they never drift from them.
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace nsf::app {

// "nsf 0.1.0" and a line each for the commit, compiler, build type, instruction set, OpenMP and
// LibTorch.
std::string version_text();

// The candidate nearest `word` (edit distance at most 2, or one it begins), "" when none is near.
std::string nearest_name(const std::string& word, const std::vector<std::string>& candidates);

// For `nsf COMMAND ARGS...` (args[0] the first after COMMAND): "" when every option given is one
// of the command's, else the usage error naming the first that is not, with the nearest name.
// Negative numbers and everything after "--" are values, not options.
std::string unknown_option(const CLI::App& command, const std::vector<std::string>& args);

// A bash completion script for `app`'s commands and their options.
std::string bash_completion(const CLI::App& app);

// A manual page (roff, section 1) of `app`: every command with its description and options.
std::string man_page(const CLI::App& app);

// Adds `nsf completion` and `nsf man`, which print the two above.
void add_self_description_commands(CLI::App& app);

}  // namespace nsf::app
