#include "nn/zip_entries.h"

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

}  // namespace

bool zip_directory(const std::string& b, size_t comment, const std::string& what,
                   const std::string& path, std::vector<ZipEntry>& out) {
  out.clear();
  const auto bad = [&](const std::string& why) {
    fail(what, " ", path, " is damaged: ", why,
         "; it was changed after nsf wrote it. Copy it again or retrain");
  };
  if (b.size() < kEndRecord + comment) bad("it is too short for an archive");
  const size_t end = b.size() - comment - kEndRecord;
  if (u32(b, end) != kEndSignature) bad("its zip end record is missing");
  const size_t entries = u16(b, end + 10);
  const uint32_t dir_size = u32(b, end + 12), dir_at = u32(b, end + 16);
  if (entries == 0xffff || dir_size == 0xffffffffu || dir_at == 0xffffffffu) return false;
  if (uint64_t(dir_at) + dir_size > end) bad("its zip directory lies outside the file");
  size_t at = dir_at;
  for (size_t e = 0; e < entries; ++e) {
    if (at + kCentralHeader > end || u32(b, at) != kCentralSignature)
      bad("its zip directory is cut short (entry " + std::to_string(e + 1) + ")");
    ZipEntry z;
    z.method = u16(b, at + 10), z.crc = u32(b, at + 16);
    z.packed = u32(b, at + 20), z.size = u32(b, at + 24);
    const size_t name = u16(b, at + 28), extra = u16(b, at + 30), note = u16(b, at + 32);
    const uint32_t local = u32(b, at + 42);
    if (at + kCentralHeader + name > end) bad("a zip directory entry's name runs past it");
    z.name = b.substr(at + kCentralHeader, name);
    if (z.packed == 0xffffffffu || z.size == 0xffffffffu || local == 0xffffffffu) {
      out.clear();
      return false;  // zip64
    }
    // Torch stores tensors as they are and deflates its class sources; deflate packs at most
    // 1,032:1, so a larger stated size is damage, not something to allocate.
    if ((z.method != 0 && z.method != 8) || (z.method == 0 && z.packed != z.size) ||
        (z.method == 8 && uint64_t(z.size) > 1032ull * z.packed + 64))
      bad("its entry '" + z.name + "' has a packing nsf does not write");
    if (uint64_t(local) + kLocalHeader > dir_at || u32(b, local) != kLocalSignature)
      bad("its entry '" + z.name + "' has no header where the directory says");
    z.data = uint64_t(local) + kLocalHeader + u16(b, local + 26) + u16(b, local + 28);
    if (z.data + z.packed > dir_at) bad("its entry '" + z.name + "' runs past the data");
    out.push_back(std::move(z));
    at += kCentralHeader + name + extra + note;
  }
  return true;
}

}  // namespace nsf
