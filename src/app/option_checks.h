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

}  // namespace nsf::app
