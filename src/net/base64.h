#pragma once
// Base64 (RFC 4648 §4, with padding), for the WebSocket handshake's keys.
#include <cstddef>
#include <optional>
#include <string>

namespace nsf::net {

std::string base64_encode(const void* data, size_t size);
// The bytes of a padded base64 text; nullopt when it is not one (a stray character, a bad length).
std::optional<std::string> base64_decode(const std::string& text);

}  // namespace nsf::net
