#pragma once
// Packs numbers into byte buffers with a chosen byte order, for the binary export formats (PLY
// and VTU are little-endian, legacy VTK is big-endian whatever the machine).
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>

namespace nsf {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "the binary writers assume a little-endian host (x86-64, arm64)");

template <typename T>
void put_le(std::string& buf, T value) {
  static_assert(std::is_arithmetic_v<T>);
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  buf.append(bytes, sizeof(T));
}

template <typename T>
void put_be(std::string& buf, T value) {
  static_assert(std::is_arithmetic_v<T>);
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  for (size_t i = sizeof(T); i-- > 0;) buf.push_back(bytes[i]);
}

}  // namespace nsf
