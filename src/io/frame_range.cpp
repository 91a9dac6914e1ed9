#include "io/frame_range.h"

#include <cerrno>
#include <cstdlib>
#include <optional>

#include "core/error.h"

namespace nsf {

namespace {

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts(1);
  for (char c : s) {
    if (c == sep) {
      parts.emplace_back();
    } else {
      parts.back() += c;
    }
  }
  return parts;
}

std::optional<long> parse_int(const std::string& part, const std::string& spec) {
  size_t b = part.find_first_not_of(" \t"), e = part.find_last_not_of(" \t");
  if (b == std::string::npos) return std::nullopt;  // empty: use the default
  const std::string t = part.substr(b, e - b + 1);
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(t.c_str(), &end, 10);
  if (*end != '\0' || errno == ERANGE)
    fail("--frames '", spec, "': '", t, "' is not an integer (use a:b:step, e.g. 0:40:2)");
  return v;
}

}  // namespace

std::vector<size_t> parse_frame_range(const std::string& spec, size_t frame_count) {
  if (frame_count == 0) fail("the run has no frames");
  const std::vector<std::string> parts = split(spec, ':');
  if (parts.size() > 3) fail("--frames '", spec, "': use a:b:step, e.g. 0:40:2");
  const long n = static_cast<long>(frame_count);
  const auto from_end = [&](long i) { return i < 0 ? i + n : i; };

  const long step = parts.size() == 3 ? parse_int(parts[2], spec).value_or(1) : 1;
  if (step <= 0) fail("--frames '", spec, "': the step must be >= 1");
  const std::optional<long> a = parse_int(parts[0], spec);
  if (parts.size() == 1) {
    if (!a) return parse_frame_range(":", frame_count);
    const long k = from_end(*a);
    if (k < 0 || k >= n)
      fail("--frames '", spec, "': frame ", *a, " does not exist; the run has ", n,
           " frames (0 to ", n - 1, ")");
    return {static_cast<size_t>(k)};
  }
  const long first = from_end(a.value_or(0));
  const long last = from_end(parse_int(parts[1], spec).value_or(n));  // exclusive
  if (first < 0 || first >= n)
    fail("--frames '", spec, "': start ", a.value_or(0), " is outside the run's ", n,
         " frames (0 to ", n - 1, ")");
  if (last > n)
    fail("--frames '", spec, "': end ", last, " is past the run's ", n,
         " frames (the end is excluded; use ", n, " or leave it out for the last frame)");
  std::vector<size_t> out;
  for (long k = first; k < last; k += step) out.push_back(static_cast<size_t>(k));
  if (out.empty()) fail("--frames '", spec, "' selects no frames (the end is excluded)");
  return out;
}

}  // namespace nsf
