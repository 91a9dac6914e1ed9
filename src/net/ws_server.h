#pragma once
// A single-threaded WebSocket + HTTP server over poll() and non-blocking sockets (RFC 6455,
// net/websocket.h). GET / answers a page given by the host; any other GET that asks for an upgrade
// becomes a WebSocket. The host calls poll() between its own work; nothing in it blocks.
//
// Each client has a bounded send queue: broadcast() encodes a message once and queues it for every
// client; a client whose queue already holds max_queue messages or max_queue_bytes bytes loses that
// message (counted), so a slow reader never holds up the others or the host, and its memory stays
// bounded. Every frame counts against the cap, pongs included: a client that pings faster than it
// reads is dropped once its pong would not fit, and a client whose queue is full is not read from
// until it drains. A client that sends anything malformed (bad HTTP, a protocol error, an
// oversized or fragmented message, a message the host's handler rejects) is dropped with one log
// line; so is a connection that takes longer than header_timeout_s to send its request head or is
// silent for idle_timeout_s before it is upgraded (slowloris), and one address may hold at most
// max_pending_per_address such connections. Requests are checked against an OriginPolicy
// (net/origin_policy.h: Host and, for a WebSocket, Origin) and refused with 403 when they fail.
// Everything logged passes through log_safe (net/log_text.h): a client cannot forge a log line.
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "net/origin_policy.h"

namespace nsf::net {

struct ServerOptions {
  std::string bind = "127.0.0.1";            // an IPv4 address; "0.0.0.0" for every interface
  int port = 8080;                           // 0: an ephemeral port (port() says which)
  size_t max_message = 4096;                 // bytes of one incoming message (payload)
  size_t max_request = 8192;                 // bytes of an HTTP request head
  size_t max_queue = 64;                     // messages waiting to be sent to one client
  size_t max_queue_bytes = size_t(4) << 20;  // their bytes (messages sent with bypass_cap aside)
  // Open connections; more are refused with 503. Lowered at start to what the process's
  // descriptor limit (ulimit -n) leaves: WsServer::max_clients says what it is.
  size_t max_clients = 256;
  // Before its upgrade (or its page) a connection must send its whole request head within
  // header_timeout_s of connecting and may not go idle_timeout_s without a byte: else 408.
  double header_timeout_s = 10;
  double idle_timeout_s = 5;
  // Connections not yet upgraded from one IP address; more from it are refused with 503.
  size_t max_pending_per_address = 16;
  std::vector<std::string> allow_hosts, allow_origins;  // net/origin_policy.h
};

using Message = std::shared_ptr<const std::string>;  // an encoded frame, shared by all queues

class WsServer {
 public:
  // Binds and listens; throws nsf::Error naming the address when it cannot.
  explicit WsServer(const ServerOptions& options);
  ~WsServer();
  WsServer(const WsServer&) = delete;
  WsServer& operator=(const WsServer&) = delete;

  int port() const { return port_; }
  // ServerOptions::max_clients, or less where the descriptor limit (`ulimit -n`, fd_limit())
  // leaves fewer descriptors free: a client the process could not have opened would have ended
  // it later, the scene file or the model unreadable for want of a descriptor.
  size_t max_clients() const { return options_.max_clients; }
  long fd_limit() const { return fd_limit_; }

  // What GET / answers (text/html).
  void set_page(std::string html) { page_ = std::move(html); }
  // A WebSocket opened: the host queues its first messages with send().
  std::function<void(int client)> on_open;
  // A text or binary message; return an empty string to accept it, else why it is malformed
  // (the client is then dropped with that reason).
  std::function<std::string(int client, const std::string& payload)> on_message;
  // One line per event worth a log (a client dropped, refused or gone); default: stderr.
  std::function<void(const std::string&)> log;

  // Waits up to timeout_ms for socket events, then accepts, reads and writes what it can.
  void poll(int timeout_ms);
  // An encoded binary (or text) message, to one client or every open WebSocket.
  static Message binary_message(const std::string& payload);
  static Message text_message(const std::string& payload);
  void send(int client, const Message& m, bool bypass_cap = false);
  void broadcast(const Message& m);

  size_t client_count() const;  // open WebSockets
  uint64_t messages_dropped() const { return dropped_; }
  uint64_t clients_dropped() const { return malformed_; }
  // Bytes queued for one client (0 when it is gone), and the most ever queued for any client;
  // messages sent with bypass_cap (shared by every client) aside.
  size_t queued_bytes(int client) const;
  // Messages sent to the client with bypass_cap that are still queued (0 when it is gone): a host
  // that sends a large payload in parts, one when the last has gone, paces it to the connection.
  size_t uncapped_queued(int client) const;
  // Whether the client is still an open WebSocket (false once it is closing or gone).
  bool is_open(int client) const;
  size_t peak_queued_bytes() const { return peak_queued_; }

 private:
  enum class State { http, websocket, closing };
  struct Queued {
    Message m;
    size_t counted;  // bytes of it that count against max_queue_bytes (0: sent with bypass_cap)
  };
  struct Client {
    int fd = -1;
    std::string peer;
    State state = State::http;
    std::string in;
    std::deque<Queued> out;
    size_t out_bytes = 0;   // counted bytes of the messages in out
    size_t out_offset = 0;  // bytes of out.front() already sent
    uint64_t dropped = 0;
    double closing_since = 0;
    std::string ip;
    double connected = 0, last_read = 0;
  };
  void accept_all();
  void read_from(int id, Client& c);
  void handle_http(int id, Client& c);
  void handle_frames(int id, Client& c);
  void write_to(Client& c);
  void enqueue(Client& c, Message m, bool counted = true);
  // Whether a message of `bytes` fits under the client's caps; whether its queue is full (then it
  // is not read from).
  bool fits(const Client& c, size_t bytes) const;
  bool backed_up(const Client& c) const;
  // The seconds until the first connection not yet upgraded runs out of time (< 0: none).
  double next_deadline(double now) const;
  void expire_slow(double now);
  // Queues a close frame (or an HTTP error) and stops reading: the socket closes once it is sent.
  // The log line says `verb` ("dropped client", "refused client") and why.
  void drop(int id, Client& c, uint16_t code, const std::string& why,
            const char* verb = "dropped client");
  void close_now(int id, Client& c, const std::string& why);
  void emit(const std::string& line) const;

  ServerOptions options_;
  OriginPolicy policy_;
  int listen_fd_ = -1;
  int port_ = 0;
  // A descriptor held in reserve: when accept() finds none left (EMFILE), it is closed to take the
  // connection and answer it 503, then opened again. Without it the connection would wait in the
  // listen queue and poll() would wake for it at once, forever.
  int spare_fd_ = -1;
  long fd_limit_ = -1;
  double accept_paused_until_ = 0;
  std::string page_;
  std::map<int, Client> clients_;
  int next_id_ = 1;
  uint64_t dropped_ = 0, malformed_ = 0;
  size_t peak_queued_ = 0;
};

}  // namespace nsf::net
