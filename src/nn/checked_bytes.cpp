#include "nn/checked_bytes.h"

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "core/crc32.h"
#include "core/error.h"
#include "core/exclusive_file.h"
#include "core/input_file.h"

namespace nsf {

namespace {

// The zip's end-of-central-directory record: 22 bytes, the last two the comment's length.
constexpr size_t kEndRecord = 22;
constexpr const char kEndSignature[] = "PK\x05\x06";
constexpr const char kTag[] = "nsf-crc32 ";
constexpr size_t kCommentLength = sizeof(kTag) - 1 + 8;

std::string hex32(uint32_t v) {
  char buf[9];
  std::snprintf(buf, sizeof buf, "%08x", static_cast<unsigned>(v));
  return buf;
}

}  // namespace

size_t checksum_comment_length() {
  return kCommentLength;
}

void add_checksum(std::string& bytes, const std::string& what, const std::string& path) {
  const size_t end = bytes.size() >= kEndRecord ? bytes.size() - kEndRecord : 0;
  if (bytes.size() < kEndRecord || bytes.compare(end, 4, kEndSignature) != 0 ||
      bytes[bytes.size() - 2] != 0 || bytes[bytes.size() - 1] != 0)
    fail("internal error: the archive for ", what, " ", path,
         " does not end in a zip end record without comment");
  const std::string comment = kTag + hex32(crc32_of(bytes.data(), bytes.size() - 2));
  bytes[bytes.size() - 2] = static_cast<char>(kCommentLength & 0xff);
  bytes[bytes.size() - 1] = static_cast<char>(kCommentLength >> 8);
  bytes += comment;
}

std::string read_checked_file(const std::string& path, const std::string& what, bool& checked) {
  std::error_code ec;
  if (const std::string kind = non_regular_kind(path); !kind.empty())
    fail(what, " ", path, " is not a regular file (it is ", kind, ")");
  if (!std::filesystem::is_regular_file(path, ec)) fail(what, " ", path, " does not exist");
  std::string bytes = read_file_bytes(path);
  const size_t n = bytes.size();
  // A checksummed file ends in the end record and the comment "nsf-crc32 xxxxxxxx".
  checked = n >= kEndRecord + kCommentLength &&
            bytes.compare(n - kCommentLength - kEndRecord, 4, kEndSignature) == 0 &&
            static_cast<unsigned char>(bytes[n - kCommentLength - 2]) == (kCommentLength & 0xff) &&
            static_cast<unsigned char>(bytes[n - kCommentLength - 1]) == (kCommentLength >> 8) &&
            bytes.compare(n - kCommentLength, sizeof(kTag) - 1, kTag) == 0;
  if (checked) {
    const std::string stored = bytes.substr(n - 8);
    const std::string actual = hex32(crc32_of(bytes.data(), n - kCommentLength - 2));
    if (stored != actual)
      fail(what, " ", path, " is damaged: its checksum does not match (stored CRC-32 ", stored,
           ", the bytes give ", actual,
           "); it was changed after nsf wrote it. Copy it again "
           "or retrain");
  }
  return bytes;
}

std::string stored_checksum(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return "";
  const std::streamoff n = in.tellg();
  const std::streamoff tail = std::streamoff(kEndRecord + kCommentLength);
  if (n < tail) return "";
  std::string end(static_cast<size_t>(tail), '\0');
  in.seekg(n - tail);
  if (!in.read(end.data(), tail)) return "";
  const bool checked =
      end.compare(0, 4, kEndSignature) == 0 && end.compare(kEndRecord, sizeof(kTag) - 1, kTag) == 0;
  return checked ? end.substr(end.size() - 8) : "";
}

}  // namespace nsf
