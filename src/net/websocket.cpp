#include "net/websocket.h"

#include <algorithm>
#include <cctype>

#include "net/base64.h"
#include "net/sha1.h"

namespace nsf::net {

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string trim(const std::string& s) {
  size_t a = 0, b = s.size();
  while (a < b && (s[a] == ' ' || s[a] == '\t')) ++a;
  while (b > a && (s[b - 1] == ' ' || s[b - 1] == '\t')) --b;
  return s.substr(a, b - a);
}

// Whether the comma-separated header value holds `token` (case-insensitive).
bool has_token(const std::string& value, const std::string& token) {
  size_t start = 0;
  while (start <= value.size()) {
    const size_t end = std::min(value.find(',', start), value.size());
    if (lower(trim(value.substr(start, end - start))) == token) return true;
    start = end + 1;
  }
  return false;
}

}  // namespace

std::string websocket_accept(const std::string& key) {
  const auto digest = sha1(key + "258EAFA5-E914-47DA-95CA-C5AB0DC85B11");
  return base64_encode(digest.data(), digest.size());
}

std::string HttpRequest::header(const std::string& name) const {
  const std::string n = lower(name);
  for (const auto& [k, v] : headers)
    if (lower(k) == n) return v;
  return "";
}

Parse parse_http_request(const std::string& buf, HttpRequest& out, size_t& consumed,
                         std::string& why) {
  const size_t end = buf.find("\r\n\r\n");
  if (end == std::string::npos) return Parse::incomplete;
  consumed = end + 4;
  out = HttpRequest();
  size_t line_end = buf.find("\r\n");
  const std::string line = buf.substr(0, line_end);
  const size_t s1 = line.find(' '), s2 = line.rfind(' ');
  if (s1 == std::string::npos || s2 == s1) {
    why = "a malformed request line";
    return Parse::error;
  }
  out.method = line.substr(0, s1);
  out.target = line.substr(s1 + 1, s2 - s1 - 1);
  out.version = line.substr(s2 + 1);
  if (out.version.rfind("HTTP/", 0) != 0 || out.target.empty()) {
    why = "a malformed request line";
    return Parse::error;
  }
  for (char c : buf.substr(0, end))
    if ((static_cast<unsigned char>(c) < 32 && c != '\r' && c != '\n' && c != '\t') || c == 127) {
      why = "a control character in the request";
      return Parse::error;
    }
  size_t pos = line_end + 2;
  while (pos < end) {
    line_end = buf.find("\r\n", pos);
    const std::string h = buf.substr(pos, line_end - pos);
    const size_t colon = h.find(':');
    if (colon == std::string::npos || colon == 0) {
      why = "a malformed header line";
      return Parse::error;
    }
    out.headers.emplace_back(h.substr(0, colon), trim(h.substr(colon + 1)));
    pos = line_end + 2;
  }
  return Parse::done;
}

std::string upgrade_problem(const HttpRequest& r) {
  if (r.method != "GET") return "the method is not GET";
  if (r.version != "HTTP/1.1") return "the version is not HTTP/1.1";
  if (!has_token(r.header("Upgrade"), "websocket")) return "no 'Upgrade: websocket'";
  if (!has_token(r.header("Connection"), "upgrade")) return "no 'Connection: Upgrade'";
  if (r.header("Sec-WebSocket-Version") != "13") return "Sec-WebSocket-Version is not 13";
  const auto key = base64_decode(r.header("Sec-WebSocket-Key"));
  if (!key || key->size() != 16) return "Sec-WebSocket-Key is not 16 bytes in base64";
  return "";
}

std::string upgrade_response(const HttpRequest& r) {
  return "HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
         "Sec-WebSocket-Accept: " +
         websocket_accept(r.header("Sec-WebSocket-Key")) + "\r\n\r\n";
}

std::string http_response(int status, const std::string& reason, const std::string& content_type,
                          const std::string& body) {
  return "HTTP/1.1 " + std::to_string(status) + " " + reason + "\r\nContent-Type: " + content_type +
         "\r\nContent-Length: " + std::to_string(body.size()) +
         "\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n" + body;
}

FrameParse parse_frame(const uint8_t* data, size_t size, bool expect_masked, size_t max_payload) {
  FrameParse r;
  const auto error = [&](uint16_t code, const char* why) {
    r.status = Parse::error;
    r.close_code = code;
    r.why = why;
    return r;
  };
  if (size < 2) return r;
  const bool fin = data[0] & 0x80;
  const uint8_t opcode = data[0] & 0x0F;
  if (data[0] & 0x70) return error(kCloseProtocol, "reserved bits set");
  if ((opcode > kBinary && opcode < kClose) || opcode > kPong)
    return error(kCloseProtocol, "an unknown opcode");
  const bool control = opcode >= kClose;
  const bool masked = data[1] & 0x80;
  if (masked != expect_masked)
    return error(kCloseProtocol, expect_masked ? "an unmasked frame" : "a masked frame");
  uint64_t len = data[1] & 0x7F;
  size_t at = 2;
  if (control && (!fin || len > 125)) return error(kCloseProtocol, "a malformed control frame");
  if (len == 126) {
    if (size < 4) return r;
    len = uint64_t(data[2]) << 8 | data[3];
    at = 4;
  } else if (len == 127) {
    if (size < 10) return r;
    len = 0;
    for (int i = 0; i < 8; ++i) len = len << 8 | data[2 + i];
    if (len >> 63) return error(kCloseProtocol, "a length with its top bit set");
    at = 10;
  }
  if (len > max_payload) return error(kCloseTooBig, "a message over the size cap");
  uint8_t mask[4] = {0, 0, 0, 0};
  if (masked) {
    if (size < at + 4) return r;
    std::copy_n(data + at, 4, mask);
    at += 4;
  }
  if (size - at < len) return r;
  r.frame.fin = fin;
  r.frame.opcode = opcode;
  r.frame.payload.assign(reinterpret_cast<const char*>(data + at), size_t(len));
  if (masked)
    for (size_t i = 0; i < r.frame.payload.size(); ++i) r.frame.payload[i] ^= char(mask[i % 4]);
  r.consumed = at + size_t(len);
  r.status = Parse::done;
  return r;
}

std::string encode_frame(uint8_t opcode, const void* payload, size_t size, const uint8_t* mask,
                         bool fin) {
  std::string out;
  out.reserve(size + 14);
  out += char((fin ? 0x80 : 0) | (opcode & 0x0F));
  const char m = mask ? char(0x80) : 0;
  if (size < 126) {
    out += char(m | char(size));
  } else if (size <= 0xFFFF) {
    out += char(m | 126);
    out += char(size >> 8);
    out += char(size & 255);
  } else {
    out += char(m | 127);
    for (int i = 7; i >= 0; --i) out += char((uint64_t(size) >> (8 * i)) & 255);
  }
  if (mask) out.append(reinterpret_cast<const char*>(mask), 4);
  const size_t at = out.size();
  out.append(static_cast<const char*>(payload), size);
  if (mask)
    for (size_t i = 0; i < size; ++i) out[at + i] ^= char(mask[i % 4]);
  return out;
}

std::string close_payload(uint16_t code, const std::string& reason) {
  std::string out;
  out += char(code >> 8);
  out += char(code & 255);
  out += reason.substr(0, 123);
  return out;
}

}  // namespace nsf::net
