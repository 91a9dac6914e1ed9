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

}  // namespace nsf::app
