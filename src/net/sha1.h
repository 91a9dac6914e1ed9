#pragma once
// SHA-1 (FIPS 180-4), for the WebSocket handshake only (RFC 6455 §4.2.2): not for security.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace nsf::net {

std::array<uint8_t, 20> sha1(const void* data, size_t size);
inline std::array<uint8_t, 20> sha1(const std::string& s) {
  return sha1(s.data(), s.size());
}

}  // namespace nsf::net
