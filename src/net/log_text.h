#pragma once
// Text from a client made safe for a log line: a client must not be able to start a line of its
// own, move the cursor or recolour a terminal through what the server logs about it.
#include <cstddef>
#include <string>

namespace nsf::net {

// `text` with every byte below 0x20, 0x7f and every byte that is not part of valid UTF-8 written as
// \xNN, the C1 controls (U+0080-U+009F) as \u00NN, and a backslash as \\ (so an escape in the
// output is always one the server wrote); cut to about `max_bytes` bytes, with "...(N bytes)"
// saying how long it was.
std::string log_safe(const std::string& text, size_t max_bytes = 240);

}  // namespace nsf::net
