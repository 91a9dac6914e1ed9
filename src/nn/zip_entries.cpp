#include "nn/zip_entries.h"

#include <zlib.h>

#include <cstdint>

#include "core/error.h"

namespace nsf {

namespace {

constexpr uint32_t kEndSignature = 0x06054b50, kCentralSignature = 0x02014b50,
                   kLocalSignature = 0x04034b50;
constexpr size_t kEndRecord = 22, kCentralHeader = 46, kLocalHeader = 30;

uint32_t u16(const std::string& b, size_t at) {
  return uint32_t(uint8_t(b[at])) | uint32_t(uint8_t(b[at + 1])) << 8;
}

uint32_t u32(const std::string& b, size_t at) {
  return u16(b, at) | u16(b, at + 2) << 16;
}

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

uint32_t crc32_of(const char* p, size_t n) {
  uLong crc = crc32(0L, Z_NULL, 0);
  constexpr size_t kChunk = size_t(1) << 30;  // crc32 takes a uInt length
  for (size_t done = 0; done < n; done += kChunk) {
    const size_t len = n - done < kChunk ? n - done : kChunk;
    crc = crc32(crc, reinterpret_cast<const Bytef*>(p + done), static_cast<uInt>(len));
  }
  return static_cast<uint32_t>(crc);
}

void check_zip_entries(const std::string& b, size_t comment, const std::string& what,
                       const std::string& path) {
  const auto bad = [&](const std::string& why) {
    fail(what, " ", path, " is damaged: ", why,
         "; it was changed after nsf wrote it. Copy it again or retrain");
  };
  if (b.size() < kEndRecord + comment) bad("it is too short for an archive");
  const size_t end = b.size() - comment - kEndRecord;
  if (u32(b, end) != kEndSignature) bad("its zip end record is missing");
  const size_t entries = u16(b, end + 10);
  const uint32_t dir_size = u32(b, end + 12), dir_at = u32(b, end + 16);
  // A zip64 archive (over 4 GiB, or 65,535 entries) marks these fields; torch writes one only
  // then, and its outer checksum is what guards it.
  if (entries == 0xffff || dir_size == 0xffffffffu || dir_at == 0xffffffffu) return;
  if (uint64_t(dir_at) + dir_size > end) bad("its zip directory lies outside the file");
  size_t at = dir_at;
  for (size_t e = 0; e < entries; ++e) {
    if (at + kCentralHeader > end || u32(b, at) != kCentralSignature)
      bad("its zip directory is cut short (entry " + std::to_string(e + 1) + ")");
    const uint32_t method = u16(b, at + 10), crc = u32(b, at + 16);
    const uint32_t packed = u32(b, at + 20), size = u32(b, at + 24);
    const size_t name = u16(b, at + 28), extra = u16(b, at + 30), note = u16(b, at + 32);
    const uint32_t local = u32(b, at + 42);
    if (at + kCentralHeader + name > end) bad("a zip directory entry's name runs past it");
    const std::string entry = b.substr(at + kCentralHeader, name);
    if (packed == 0xffffffffu || size == 0xffffffffu || local == 0xffffffffu) return;  // zip64
    // Torch stores tensors as they are and deflates its class sources; deflate packs at most
    // 1,032:1, so a larger stated size is damage, not something to allocate.
    if ((method != 0 && method != 8) || (method == 0 && packed != size) ||
        (method == 8 && uint64_t(size) > 1032ull * packed + 64))
      bad("its entry '" + entry + "' has a packing nsf does not write");
    if (uint64_t(local) + kLocalHeader > dir_at || u32(b, local) != kLocalSignature)
      bad("its entry '" + entry + "' has no header where the directory says");
    const uint64_t data = uint64_t(local) + kLocalHeader + u16(b, local + 26) + u16(b, local + 28);
    if (data + packed > dir_at) bad("its entry '" + entry + "' runs past the data");
    uint32_t actual = 0;
    if (method == 0)
      actual = crc32_of(b.data() + data, size);
    else if (!inflated_crc(b.data() + data, packed, size, actual))
      bad("its entry '" + entry + "' does not inflate to its stated size");
    if (actual != crc) bad("its entry '" + entry + "' does not match its CRC-32");
    at += kCentralHeader + name + extra + note;
  }
}

}  // namespace nsf
