#include "net/log_text.h"

#include <cstdint>
#include <cstdio>

namespace nsf::net {

namespace {

// The length of the valid UTF-8 sequence at s[i] (2-4 bytes: no overlong form, no surrogate,
// nothing past U+10FFFF), or 0 when there is none.
size_t utf8_sequence(const std::string& s, size_t i) {
  const auto at = [&](size_t k) { return static_cast<uint8_t>(s[k]); };
  const uint8_t b = at(i);
  size_t n;
  uint32_t cp;
  if (b >= 0xC2 && b <= 0xDF) {
    n = 2;
    cp = b & 0x1Fu;
  } else if (b >= 0xE0 && b <= 0xEF) {
    n = 3;
    cp = b & 0x0Fu;
  } else if (b >= 0xF0 && b <= 0xF4) {
    n = 4;
    cp = b & 0x07u;
  } else {
    return 0;
  }
  if (i + n > s.size()) return 0;
  for (size_t k = 1; k < n; ++k) {
    if ((at(i + k) & 0xC0) != 0x80) return 0;
    cp = (cp << 6) | (at(i + k) & 0x3Fu);
  }
  if ((n == 3 && cp < 0x800) || (n == 4 && cp < 0x10000) || cp > 0x10FFFF ||
      (cp >= 0xD800 && cp <= 0xDFFF))
    return 0;
  return n;
}

}  // namespace

std::string log_safe(const std::string& text, size_t max_bytes) {
  std::string out;
  char hex[8];
  size_t i = 0;
  while (i < text.size() && out.size() < max_bytes) {
    const auto b = static_cast<uint8_t>(text[i]);
    if (b == '\\') {
      out += "\\\\";
      ++i;
    } else if (b < 0x20 || b == 0x7f) {
      std::snprintf(hex, sizeof hex, "\\x%02x", b);
      out += hex;
      ++i;
    } else if (b < 0x80) {
      out += char(b);
      ++i;
    } else if (const size_t n = utf8_sequence(text, i); n == 0) {
      std::snprintf(hex, sizeof hex, "\\x%02x", b);
      out += hex;
      ++i;
    } else if (b == 0xC2 && static_cast<uint8_t>(text[i + 1]) < 0xA0) {  // C1: U+0080-U+009F
      std::snprintf(hex, sizeof hex, "\\u%04x", static_cast<uint8_t>(text[i + 1]));
      out += hex;
      i += 2;
    } else {
      out.append(text, i, n);
      i += n;
    }
  }
  if (i < text.size()) out += "...(" + std::to_string(text.size()) + " bytes)";
  return out;
}

}  // namespace nsf::net
