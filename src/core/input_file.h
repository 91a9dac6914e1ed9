#pragma once
// The input files nsf reads whole into memory and parses (a scene, a dataset manifest: JSON):
// a regular file or a pipe, at most kMaxTextInputBytes. `nsf simulate /dev/zero` used to read
// 2.2 GB before dying of std::bad_alloc; a device is now refused at once, and a pipe or file
// larger than the cap after reading one byte more than it (docs/OUTPUT.md, "Bad input").
#include <cstdint>
#include <string>

namespace nsf {

// 64 MiB: a scene is a few kilobytes of JSON, a manifest of 10,000 runs about one megabyte.
constexpr std::uintmax_t kMaxTextInputBytes = std::uintmax_t(64) << 20;

// What a path names when it is not a regular file: "a directory", "a character device", "a block
// device", "a socket", "a FIFO"; "" for a regular file or nothing at all.
std::string non_regular_kind(const std::string& path);

// The bytes of `path`, which `what` names in messages ("scene file"). Throws nsf::Error
// "<what> '<path>' ..." when the file is missing or unreadable, is not a regular file or a pipe
// (a device, a directory), or holds more than `max_bytes`.
std::string read_input_file(const std::string& path, const std::string& what,
                            std::uintmax_t max_bytes = kMaxTextInputBytes);

}  // namespace nsf
