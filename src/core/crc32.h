#pragma once
// CRC-32 (the zip and zlib polynomial, reflected 0xEDB88320), without zlib: the model file's
// checksum (nn/checked_bytes.h) is verified by the torch-free runtime too.
#include <cstddef>
#include <cstdint>

namespace nsf {

// The CRC-32 of n bytes at p, continuing from `crc` (0 to start), as zlib's crc32(crc, p, n).
uint32_t crc32_of(const char* p, size_t n, uint32_t crc = 0);

}  // namespace nsf
