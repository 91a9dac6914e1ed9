#pragma once
// The zip container torch writes an archive in (the model file, the training checkpoint) carries
// a CRC-32 of every entry, which torch's reader does not check. nsf's own checksum covers the
// whole file, but a file whose outer checksum was made to match again still reaches torch's
// TorchScript parser, which crashes on some damaged class sources. Checking each entry against
// the central directory first refuses such a file by name.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace nsf {

// One entry of a zip's central directory, checked to lie inside the file.
struct ZipEntry {
  std::string name;
  uint32_t method = 0;  // 0 stored, 8 deflated
  uint32_t crc = 0, packed = 0, size = 0;
  uint64_t data = 0;  // offset of its bytes in the archive
};

// The entries of `bytes` (a whole archive, `comment` bytes of zip comment at its end). Throws
// nsf::Error naming `what` and `path` when the directory is malformed. Returns false, with no
// entries, for a zip64 archive (over 4 GiB or 65,535 entries): torch writes one only then, and
// nsf's outer checksum is what guards it. Needs neither torch nor zlib.
bool zip_directory(const std::string& bytes, size_t comment, const std::string& what,
                   const std::string& path, std::vector<ZipEntry>& entries);

// Throws nsf::Error naming `what` and `path` when `bytes` (a whole archive, `comment` bytes of
// zip comment at its end) is not a well-formed stored zip whose entries match their CRC-32s.
// (zip_check.cpp: inflates the deflated entries with zlib.)
void check_zip_entries(const std::string& bytes, size_t comment, const std::string& what,
                       const std::string& path);

}  // namespace nsf
