#include <zlib.h>

#include "core/crc32.h"
#include "core/error.h"
#include "nn/zip_entries.h"

namespace nsf {

namespace {

// The CRC-32 of a deflated entry's `size` bytes once inflated; false when they do not inflate to
// exactly that many.
bool inflated_crc(const char* p, size_t packed, size_t size, uint32_t& crc) {
  std::string out(size, '\0');
  z_stream z{};
  if (inflateInit2(&z, -15) != Z_OK) return false;  // raw deflate, as in a zip
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(p));
  z.avail_in = static_cast<uInt>(packed);
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(size);
  const int r = inflate(&z, Z_FINISH);
  const bool whole = r == Z_STREAM_END && z.total_out == size;
  inflateEnd(&z);
  if (whole) crc = crc32_of(out.data(), size);
  return whole;
}

}  // namespace

void check_zip_entries(const std::string& b, size_t comment, const std::string& what,
                       const std::string& path) {
  std::vector<ZipEntry> entries;
  if (!zip_directory(b, comment, what, path, entries)) return;  // zip64: the outer checksum
  for (const ZipEntry& z : entries) {
    uint32_t actual = 0;
    if (z.method == 0)
      actual = crc32_of(b.data() + z.data, z.size);
    else if (!inflated_crc(b.data() + z.data, z.packed, z.size, actual))
      fail(what, " ", path, " is damaged: its entry '", z.name,
           "' does not inflate to its stated size; it was changed after nsf wrote it. Copy it "
           "again or retrain");
    if (actual != z.crc)
      fail(what, " ", path, " is damaged: its entry '", z.name,
           "' does not match its CRC-32; it was changed after nsf wrote it. Copy it again or "
           "retrain");
  }
}

}  // namespace nsf
