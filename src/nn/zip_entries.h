#pragma once
// The zip container torch writes an archive in (the model file, the training checkpoint) carries
// a CRC-32 of every entry, which torch's reader does not check. nsf's own checksum covers the
// whole file, but a file whose outer checksum was made to match again still reaches torch's
// TorchScript parser, which crashes on some damaged class sources. Checking each entry against
// the central directory first refuses such a file by name.
#include <cstddef>
#include <cstdint>
#include <string>

namespace nsf {

// The CRC-32 of n bytes at p (zlib's, in chunks: its length argument is 32-bit).
uint32_t crc32_of(const char* p, size_t n);

// Throws nsf::Error naming `what` and `path` when `bytes` (a whole archive, `comment` bytes of
// zip comment at its end) is not a well-formed stored zip whose entries match their CRC-32s.
void check_zip_entries(const std::string& bytes, size_t comment, const std::string& what,
                       const std::string& path);

}  // namespace nsf
