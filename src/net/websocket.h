#pragma once
// RFC 6455 (WebSocket) without sockets: the HTTP upgrade handshake and frame encoding and parsing,
// incremental over whatever bytes have arrived. The server (net/ws_server.h) and the tests' client
// share it. Fragmented messages are parsed (each frame with its FIN bit) but the server refuses
// them: its messages are small commands.
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace nsf::net {

// Sec-WebSocket-Accept for a client's Sec-WebSocket-Key: base64(SHA-1(key + the RFC's GUID)).
std::string websocket_accept(const std::string& key);

struct HttpRequest {
  std::string method, target, version;
  std::vector<std::pair<std::string, std::string>> headers;  // names as sent, values trimmed
  // The value of header `name` (case-insensitive), "" when absent.
  std::string header(const std::string& name) const;
};

enum class Parse { incomplete, done, error };

// Parses an HTTP/1.1 request head (up to the blank line) at the start of `buf`. done: `out` and
// `consumed` (the head's bytes) are set; error: `why` says what is wrong with it.
Parse parse_http_request(const std::string& buf, HttpRequest& out, size_t& consumed,
                         std::string& why);

// Empty when `r` is a valid WebSocket upgrade (GET, HTTP/1.1, Upgrade: websocket, Connection:
// Upgrade, a 16-byte Sec-WebSocket-Key, version 13); else what is missing.
std::string upgrade_problem(const HttpRequest& r);
// The server's 101 answer to a valid upgrade request.
std::string upgrade_response(const HttpRequest& r);
// A complete HTTP response with Content-Length and Connection: close.
std::string http_response(int status, const std::string& reason, const std::string& content_type,
                          const std::string& body);

enum Opcode : uint8_t {
  kContinuation = 0x0,
  kText = 0x1,
  kBinary = 0x2,
  kClose = 0x8,
  kPing = 0x9,
  kPong = 0xA
};

// Close status codes (RFC 6455 §7.4.1) the server sends.
enum CloseCode : uint16_t {
  kCloseNormal = 1000,
  kCloseGoingAway = 1001,
  kCloseProtocol = 1002,
  kCloseUnsupported = 1003,
  kCloseInvalidData = 1007,
  kClosePolicy = 1008,
  kCloseTooBig = 1009
};

struct Frame {
  bool fin = true;
  uint8_t opcode = kText;
  std::string payload;  // unmasked
};

struct FrameParse {
  Parse status = Parse::incomplete;
  size_t consumed = 0;      // bytes of the frame (done)
  Frame frame;              // done
  uint16_t close_code = 0;  // error: what to close with
  std::string why;          // error
};

// One frame at the start of [data, data + size). A server parses with expect_masked (a client's
// frames must be masked, §5.1), a client without (a server's must not be). A payload longer than
// max_payload is an error (1009) as soon as its length is read, before it arrives; so are reserved
// bits, unknown opcodes, control frames that are fragmented or over 125 bytes, and a 64-bit
// length with its top bit set (1002).
FrameParse parse_frame(const uint8_t* data, size_t size, bool expect_masked, size_t max_payload);

// A frame holding `payload`; masked with `mask` (4 bytes) when it is given, as a client must.
std::string encode_frame(uint8_t opcode, const void* payload, size_t size,
                         const uint8_t* mask = nullptr, bool fin = true);
inline std::string encode_frame(uint8_t opcode, const std::string& payload,
                                const uint8_t* mask = nullptr, bool fin = true) {
  return encode_frame(opcode, payload.data(), payload.size(), mask, fin);
}
// A close frame's payload: the code (big-endian) and a reason cut to fit 125 bytes.
std::string close_payload(uint16_t code, const std::string& reason);

}  // namespace nsf::net
