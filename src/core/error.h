#pragma once
// One exception type for every user-facing failure: bad scene values, missing files, a blown-up
// simulation. The CLI prints what() and exits non-zero, so messages must name the problem.
#include <sstream>
#include <stdexcept>
#include <string>

namespace nsf {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& msg) : std::runtime_error(msg) {}
};

// Builds a message from streamable parts: fail("particle ", p, " left the domain").
template <typename... Args>
[[noreturn]] void fail(const Args&... parts) {
  std::ostringstream os;
  (os << ... << parts);
  throw Error(os.str());
}

}  // namespace nsf
