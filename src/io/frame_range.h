#pragma once
// Which frames of a run a command works on: "a:b:step" with Python slice rules, because that is
// what people who post-process runs in numpy already know.
//   ""  or ":"   every frame          "10:"   frame 10 to the last
//   "::5"        every fifth frame    "-1"    the last frame only
//   "0:20:2"     0, 2, ..., 18 (b is excluded; negative a or b count from the end)
#include <cstddef>
#include <string>
#include <vector>

namespace nsf {

// The selected frame indices in increasing order. Fails with a message quoting `spec` for bad
// syntax, a step <= 0, an index out of range or an empty selection.
std::vector<size_t> parse_frame_range(const std::string& spec, size_t frame_count);

}  // namespace nsf
