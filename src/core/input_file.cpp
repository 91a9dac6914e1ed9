#include "core/input_file.h"

#include <filesystem>
#include <fstream>
#include <system_error>

#include "core/error.h"

namespace nsf {

namespace fs = std::filesystem;

namespace {

std::string size_text(std::uintmax_t bytes) {
  if (bytes % (std::uintmax_t(1) << 20) == 0) return std::to_string(bytes >> 20) + " MiB";
  return std::to_string(bytes) + " bytes";
}

}  // namespace

std::string non_regular_kind(const std::string& path) {
  std::error_code ec;
  switch (fs::status(path, ec).type()) {
    case fs::file_type::directory:
      return "a directory";
    case fs::file_type::character:
      return "a character device";
    case fs::file_type::block:
      return "a block device";
    case fs::file_type::socket:
      return "a socket";
    case fs::file_type::fifo:
      return "a FIFO";
    default:
      return "";
  }
}

std::string read_input_file(const std::string& path, const std::string& what,
                            std::uintmax_t max_bytes) {
  const std::string kind = non_regular_kind(path);
  // A pipe is read like a file (a scene from a process substitution, <(...)); a device is not:
  // /dev/zero would be read up to the cap, /dev/tty would wait for the user.
  if (!kind.empty() && kind != "a FIFO")
    fail(what, " '", path, "' is not a regular file (it is ", kind, ")");
  const std::string too_large = " is larger than " + size_text(max_bytes) +
                                ", the most nsf reads of one (is it the right file?)";
  std::error_code ec;
  if (kind.empty() && fs::exists(path, ec) && fs::file_size(path, ec) > max_bytes && !ec)
    fail(what, " '", path, "'", too_large);
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(what, " '", path, "' cannot be opened (missing or unreadable)");
  std::string bytes;
  char buf[65536];
  while (in.read(buf, sizeof buf) || in.gcount() > 0) {
    bytes.append(buf, size_t(in.gcount()));
    if (bytes.size() > max_bytes) fail(what, " '", path, "'", too_large);
  }
  if (in.bad()) fail(what, " '", path, "' cannot be read");
  return bytes;
}

}  // namespace nsf
