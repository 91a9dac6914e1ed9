#pragma once
// Small string helpers for messages.
#include <string>
#include <vector>

namespace nsf {

// "a, b, c" (or with another separator); "" for none.
inline std::string join(const std::vector<std::string>& parts,
                        const std::string& separator = ", ") {
  std::string out;
  for (const std::string& p : parts) out += (out.empty() ? "" : separator) + p;
  return out;
}

}  // namespace nsf
