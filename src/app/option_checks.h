#pragma once
// The range check every numeric option of nsf carries. CLI::Range lets NaN through (every
// comparison with NaN is false) and says nothing of infinity; in_range refuses both, and values
// outside [lo, hi]. CLI11 puts the option's name in front of the message ("--epochs: nan is not
// a finite number") and exits with its usage-error status.
#include <CLI/CLI.hpp>
#include <cmath>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "core/error.h"

namespace nsf::app {

template <typename T>
CLI::Validator in_range(T lo, T hi) {
  std::ostringstream os;
  os << lo << " to " << hi;
  const std::string range = os.str();
  return CLI::Validator(
      [lo, hi, range](std::string& input) -> std::string {
        T value{};
        if (!CLI::detail::lexical_cast(input, value))
          return "'" + input + "' is not " +
                 (std::is_integral_v<T> ? "a whole number" : "a number") + " (" + range + ")";
        if constexpr (std::is_floating_point_v<T>)
          if (!std::isfinite(value)) return input + " is not a finite number (" + range + ")";
        if (value < lo || value > hi) return input + " is out of range (" + range + ")";
        return std::string();
      },
      "in " + range);
}

// A list option, "a" or "a,b,c", each value checked by in_range(lo, hi). Given twice, it is a
// usage error naming it: CLI11 would append the second list to the first (--steps 5 --steps
// 6,7 read as 5,6,7).
template <typename T>
CLI::Option* add_list_option(CLI::App* cmd, const std::string& name, std::vector<T>& out,
                             const std::string& help, T lo, T hi) {
  const CLI::Validator check = in_range(lo, hi);
  const std::string flag = name.substr(0, name.find(','));
  return cmd
      ->add_option_function<std::string>(
          name,
          [&out, check, flag](const std::string& text) {
            out.clear();
            std::string rest = text + ",";
            for (size_t at = rest.find(','); at != std::string::npos; at = rest.find(',')) {
              std::string item = rest.substr(0, at);
              rest.erase(0, at + 1);
              const std::string problem = check(item);
              if (!problem.empty()) throw CLI::ValidationError(flag, problem);
              T value{};
              CLI::detail::lexical_cast(item, value);
              out.push_back(value);
            }
          },
          help)
      ->type_name(std::is_integral_v<T> ? "INT[,INT,INT]" : "NUM[,NUM,NUM]");
}

// --set KEY=VALUE: a value without '=' or without a key is a usage error (exit status 2); what the
// key names and the value are the scene's to check (an error naming the override, exit 1).
inline CLI::Validator override_syntax() {
  return CLI::Validator(
      [](std::string& input) -> std::string {
        const size_t eq = input.find('=');
        if (eq == std::string::npos || eq == 0)
          return "'" + input + "' must look like KEY=VALUE, e.g. simulation.dt=1e-4";
        return std::string();
      },
      "");
}

// A value the command parses itself (--size 960x720, --frames 0:40:2, --camera eye=...): the
// parser's nsf::Error becomes a usage error (exit status 2, "nsf: usage error: "), as CLI11's own
// checks are. Its message names the option.
template <typename Parse>
auto parse_option_value(Parse&& parse) -> decltype(parse()) {
  try {
    return parse();
  } catch (const Error& e) {
    throw CLI::ValidationError(std::string(e.what()));
  }
}

}  // namespace nsf::app
