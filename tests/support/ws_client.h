#pragma once
// A small blocking WebSocket client for the tests of the server (net/ws_server.h) and of
// `nsf serve`, on the same framing code (net/websocket.h).
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "net/base64.h"
#include "net/websocket.h"

namespace nsf::testing {

class WsClient {
 public:
  WsClient() = default;
  WsClient(const WsClient&) = delete;
  WsClient& operator=(const WsClient&) = delete;
  ~WsClient() { close(); }

  // Set before connecting: the address to connect from (another 127.x.y.z is another client
  // address on loopback; "": the system's choice), and SO_RCVBUF (0: the system's).
  std::string from;
  int receive_buffer = 0;
  // Set before connect(): the Host header ("": 127.0.0.1:port) and Origin header ("": none, as a
  // program sends; a browser always sends one).
  std::string host, origin;

  // A TCP connection to 127.0.0.1:port; false when refused (or `from` cannot be bound).
  bool connect_tcp(int port) {
    fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (receive_buffer > 0)
      ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &receive_buffer, sizeof receive_buffer);
    if (!from.empty()) {
      sockaddr_in local{};
      local.sin_family = AF_INET;
      if (::inet_pton(AF_INET, from.c_str(), &local.sin_addr) != 1 ||
          ::bind(fd_, reinterpret_cast<sockaddr*>(&local), sizeof local) != 0)
        return false;
    }
    sockaddr_in sa{};
    sa.sin_family = AF_INET;
    sa.sin_port = htons(uint16_t(port));
    sa.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    return ::connect(fd_, reinterpret_cast<sockaddr*>(&sa), sizeof sa) == 0;
  }
  // connect_tcp, then the upgrade handshake; false unless the server answers 101 with the right
  // Sec-WebSocket-Accept (response_head() says what it answered). `then`: bytes sent in the same
  // write as the handshake, before its answer (frames of a client that does not wait).
  bool connect(int port, const std::string& path = "/stream", const std::string& then = "") {
    if (!connect_tcp(port)) return false;
    std::string key_bytes(16, '\0');
    for (char& c : key_bytes) c = char(rng_());
    const std::string key = net::base64_encode(key_bytes.data(), key_bytes.size());
    send_raw("GET " + path + " HTTP/1.1\r\nHost: " + host_header(port) +
             "\r\nUpgrade: websocket\r\n" + (origin.empty() ? "" : "Origin: " + origin + "\r\n") +
             "Connection: Upgrade\r\nSec-WebSocket-Key: " + key +
             "\r\nSec-WebSocket-Version: 13\r\n\r\n" + then);
    const std::optional<std::string> head = read_head(5.0);
    if (!head) return false;
    head_ = *head;
    return head->rfind("HTTP/1.1 101", 0) == 0 &&
           head->find("Sec-WebSocket-Accept: " + net::websocket_accept(key)) != std::string::npos;
  }
  // The head of the server's answer to connect() ("" before one came).
  const std::string& response_head() const { return head_; }
  // An HTTP GET; the whole response (the server closes after it), or "" on timeout.
  std::string http_get(int port, const std::string& path, double timeout_s = 5.0) {
    if (!connect_tcp(port)) return "";
    send_raw("GET " + path + " HTTP/1.1\r\nHost: " + host_header(port) + "\r\n\r\n");
    return read_until_eof(timeout_s);
  }
  bool send_raw(const std::string& bytes) {
    size_t at = 0;
    while (at < bytes.size()) {
      const ssize_t w = ::send(fd_, bytes.data() + at, bytes.size() - at, MSG_NOSIGNAL);
      if (w <= 0) return false;
      at += size_t(w);
    }
    return true;
  }
  // A masked frame, as a client must send.
  bool send_frame(uint8_t opcode, const std::string& payload, bool fin = true) {
    uint8_t mask[4];
    for (uint8_t& m : mask) m = uint8_t(rng_());
    return send_raw(net::encode_frame(opcode, payload, mask, fin));
  }
  bool send_text(const std::string& s) { return send_frame(net::kText, s); }

  // The next frame from the server (pings and pongs included), or nullopt on timeout, a closed
  // socket or a protocol error.
  std::optional<net::Frame> next_frame(double timeout_s = 5.0) {
    const auto end = deadline(timeout_s);
    for (;;) {
      const net::FrameParse f = net::parse_frame(reinterpret_cast<const uint8_t*>(buf_.data()),
                                                 buf_.size(), false, size_t(1) << 30);
      if (f.status == net::Parse::error) return std::nullopt;
      if (f.status == net::Parse::done) {
        buf_.erase(0, f.consumed);
        return f.frame;
      }
      if (!fill(end)) return std::nullopt;
    }
  }
  // The frames already complete after one non-blocking read of at most max_bytes (none if
  // nothing came). bytes_read() counts what drain() took.
  std::vector<net::Frame> drain(size_t max_bytes = SIZE_MAX) {
    char tmp[65536];
    while (max_bytes > 0) {
      const ssize_t r = ::recv(fd_, tmp, std::min(sizeof tmp, max_bytes), MSG_DONTWAIT);
      if (r > 0) {
        buf_.append(tmp, size_t(r));
        bytes_read_ += size_t(r);
        max_bytes -= size_t(r);
        continue;
      }
      if (r == 0) eof_ = true;
      break;
    }
    std::vector<net::Frame> out;
    size_t at = 0;
    for (;;) {
      const net::FrameParse f = net::parse_frame(reinterpret_cast<const uint8_t*>(buf_.data()) + at,
                                                 buf_.size() - at, false, size_t(1) << 30);
      if (f.status != net::Parse::done) break;
      at += f.consumed;
      out.push_back(f.frame);
    }
    buf_.erase(0, at);
    return out;
  }
  bool eof() const { return eof_; }
  size_t bytes_read() const { return bytes_read_; }
  // Whether the server closed the connection (a close frame or EOF) within timeout_s; data
  // frames before it are skipped.
  bool closed_by_server(double timeout_s = 5.0) {
    const auto end = deadline(timeout_s);
    while (clock::now() < end) {
      const auto f = next_frame(std::chrono::duration<double>(end - clock::now()).count());
      if (!f) return eof_;
      if (f->opcode == net::kClose) return true;
    }
    return false;
  }
  // Everything the server sends until it closes the connection ("" past timeout_s without EOF).
  std::string read_until_eof(double timeout_s = 5.0) {
    const auto end = deadline(timeout_s);
    while (!eof_ && fill(end)) {
    }
    return eof_ ? buf_ : "";
  }
  void close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }
  int fd() const { return fd_; }

 private:
  using clock = std::chrono::steady_clock;
  std::string host_header(int port) const {
    return host.empty() ? "127.0.0.1:" + std::to_string(port) : host;
  }
  static clock::time_point deadline(double s) {
    return clock::now() +
           std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(s));
  }
  // Reads what is there (waiting until `end`); false on timeout or EOF.
  bool fill(clock::time_point end) {
    const double left = std::chrono::duration<double>(end - clock::now()).count();
    if (left <= 0) return false;
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, int(left * 1000) + 1) <= 0) return false;
    char tmp[65536];
    const ssize_t r = ::recv(fd_, tmp, sizeof tmp, 0);
    if (r <= 0) {
      eof_ = true;
      return false;
    }
    buf_.append(tmp, size_t(r));
    return true;
  }
  std::optional<std::string> read_head(double timeout_s) {
    const auto end = deadline(timeout_s);
    for (;;) {
      const size_t at = buf_.find("\r\n\r\n");
      if (at != std::string::npos) {
        std::string head = buf_.substr(0, at + 4);
        buf_.erase(0, at + 4);
        return head;
      }
      if (!fill(end)) return std::nullopt;
    }
  }
  int fd_ = -1;
  bool eof_ = false;
  size_t bytes_read_ = 0;
  std::string buf_, head_;
  std::mt19937 rng_{std::random_device{}()};
};

}  // namespace nsf::testing
