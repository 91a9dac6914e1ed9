#pragma once
// --steps and --widths, spelled alike by `nsf train`, `nsf demo` and `nsf report`: one value for
// all three stages (decoders g, h, l) or three, comma-separated. A width of 0 keeps the default
// (Table 1's, or the scene's "train" recipe).
#include <CLI/CLI.hpp>
#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace nsf::app {

struct TrainSizeArgs {
  std::vector<long> steps;
  std::vector<int> widths;
};

// Registers --steps and --widths on `cmd`; each help text ends with the command's defaults.
void add_train_size_options(CLI::App* cmd, TrainSizeArgs& args, const std::string& steps_default,
                            const std::string& widths_default);

// A usage error (CLI::ValidationError, exit status 2) unless `count` is 1 or 3.
void require_one_or_three(size_t count, const std::string& option, const std::string& what);

// One value repeated, or the three; `fallback` when none were given. Checks the count.
template <typename T>
std::array<T, 3> per_stage(const std::vector<T>& values, const std::array<T, 3>& fallback,
                           const std::string& option) {
  if (values.empty()) return fallback;
  require_one_or_three(values.size(), option, "stage");
  return values.size() == 1 ? std::array<T, 3>{values[0], values[0], values[0]}
                            : std::array<T, 3>{values[0], values[1], values[2]};
}

}  // namespace nsf::app
