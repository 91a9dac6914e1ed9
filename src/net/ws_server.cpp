#include "net/ws_server.h"

#include <arpa/inet.h>
#include <dirent.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <vector>

#include "core/error.h"
#include "net/log_text.h"
#include "net/websocket.h"

namespace nsf::net {

namespace {

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

constexpr double kCloseGraceS = 2.0;    // a closing socket gets this long to take its last bytes
constexpr size_t kReadPerPoll = 65536;  // bytes read from one client per poll(), at most
constexpr size_t kLogLine = 400;        // bytes of a log line, at most (client text escaped)

const char* reason_phrase(int status) {
  switch (status) {
    case 403:
      return "Forbidden";
    case 408:
      return "Request Timeout";
    case 431:
      return "Request Header Fields Too Large";
    case 503:
      return "Service Unavailable";
    default:
      return "Bad Request";
  }
}

std::string seconds(double s) {
  char b[32];
  std::snprintf(b, sizeof b, "%g s", s);
  return b;
}

// Descriptors this process has open now (/proc/self/fd), or -1 where that cannot be read.
long open_descriptors() {
  DIR* d = ::opendir("/proc/self/fd");
  if (!d) return -1;
  long n = 0;
  while (const dirent* e = ::readdir(d)) n += e->d_name[0] != '.';
  ::closedir(d);
  return n - 1;  // the directory's own
}

// Descriptors kept free beyond the clients': the spare, one to answer a refused connection, and
// the files the host opens while it serves.
constexpr long kReservedDescriptors = 8;

// Answers a connection not taken (an HTTP error) and closes it.
void refuse_now(int fd, int status, const std::string& body) {
  const std::string r = http_response(status, reason_phrase(status), "text/plain", body);
  [[maybe_unused]] ssize_t w = ::send(fd, r.data(), r.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
  ::close(fd);
}

}  // namespace

WsServer::WsServer(const ServerOptions& options) : options_(options) {
  in_addr addr{};
  if (::inet_pton(AF_INET, options.bind.c_str(), &addr) != 1)
    fail("--bind ", options.bind, ": not an IPv4 address (e.g. 127.0.0.1 or 0.0.0.0)");
  if (options.port < 0 || options.port > 65535)
    fail("--port ", options.port, ": not a port number (0-65535)");
  listen_fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (listen_fd_ < 0) fail("cannot open a socket: ", std::strerror(errno));
  const int one = 1;
  ::setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  sockaddr_in sa{};
  sa.sin_family = AF_INET;
  sa.sin_port = htons(uint16_t(options.port));
  sa.sin_addr = addr;
  if (::bind(listen_fd_, reinterpret_cast<sockaddr*>(&sa), sizeof sa) < 0 ||
      ::listen(listen_fd_, 64) < 0) {
    const std::string why = std::strerror(errno);
    ::close(listen_fd_);
    fail("cannot listen on ", options.bind, ":", options.port, ": ", why);
  }
  socklen_t len = sizeof sa;
  ::getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&sa), &len);
  port_ = ntohs(sa.sin_port);
  rlimit limit{};
  const long open = open_descriptors();
  if (::getrlimit(RLIMIT_NOFILE, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY && open >= 0) {
    fd_limit_ = long(limit.rlim_cur);
    const long room = fd_limit_ - open - 1 - kReservedDescriptors;  // 1: the spare below
    if (long(options_.max_clients) > room) options_.max_clients = size_t(std::max(1L, room));
  }
  spare_fd_ = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  policy_.bind = options.bind;
  policy_.port = port_;
  policy_.allow_hosts = options.allow_hosts;
  policy_.allow_origins = options.allow_origins;
}

WsServer::~WsServer() {
  for (auto& [id, c] : clients_) ::close(c.fd);
  if (listen_fd_ >= 0) ::close(listen_fd_);
  if (spare_fd_ >= 0) ::close(spare_fd_);
}

void WsServer::emit(const std::string& line) const {
  // The reasons in a line may quote a client (a header, a command): no raw control characters.
  const std::string safe = log_safe(line, kLogLine);
  if (log)
    log(safe);
  else
    std::cerr << safe << "\n";
}

Message WsServer::binary_message(const std::string& payload) {
  return std::make_shared<const std::string>(encode_frame(kBinary, payload));
}
Message WsServer::text_message(const std::string& payload) {
  return std::make_shared<const std::string>(encode_frame(kText, payload));
}

size_t WsServer::client_count() const {
  size_t n = 0;
  for (const auto& [id, c] : clients_) n += c.state == State::websocket;
  return n;
}

size_t WsServer::queued_bytes(int id) const {
  const auto it = clients_.find(id);
  return it == clients_.end() ? 0 : it->second.out_bytes;
}

size_t WsServer::uncapped_queued(int id) const {
  const auto it = clients_.find(id);
  if (it == clients_.end()) return 0;
  return size_t(std::count_if(it->second.out.begin(), it->second.out.end(),
                              [](const Queued& q) { return q.counted == 0; }));
}

bool WsServer::is_open(int id) const {
  const auto it = clients_.find(id);
  return it != clients_.end() && it->second.state == State::websocket;
}

bool WsServer::fits(const Client& c, size_t bytes) const {
  if (c.out.size() >= options_.max_queue) return false;
  // A queue with no counted bytes takes any one message, so one larger than the byte cap is not
  // lost for good.
  return c.out_bytes == 0 || c.out_bytes + bytes <= options_.max_queue_bytes;
}

bool WsServer::backed_up(const Client& c) const {
  return c.out.size() >= options_.max_queue || c.out_bytes >= options_.max_queue_bytes;
}

void WsServer::enqueue(Client& c, Message m, bool counted) {
  const size_t bytes = counted ? m->size() : 0;
  c.out_bytes += bytes;
  c.out.push_back({std::move(m), bytes});
  peak_queued_ = std::max(peak_queued_, c.out_bytes);
}

void WsServer::send(int id, const Message& m, bool bypass_cap) {
  auto it = clients_.find(id);
  if (it == clients_.end() || it->second.state != State::websocket) return;
  Client& c = it->second;
  if (!bypass_cap && !fits(c, m->size())) {
    ++c.dropped;
    ++dropped_;
    return;
  }
  enqueue(c, m, !bypass_cap);
}

void WsServer::broadcast(const Message& m) {
  for (auto& [id, c] : clients_) send(id, m);
}

void WsServer::poll(int timeout_ms) {
  std::vector<pollfd> fds;
  std::vector<int> ids;
  const bool accepting = now_s() >= accept_paused_until_;
  fds.push_back({listen_fd_, short(accepting ? POLLIN : 0), 0});
  ids.push_back(0);
  if (!accepting) timeout_ms = std::min(timeout_ms, 100);
  for (const auto& [id, c] : clients_) {
    // A client whose queue is full is not read from: what it sends waits in its own socket.
    short ev = c.state == State::closing || backed_up(c) ? 0 : POLLIN;
    if (!c.out.empty()) ev |= POLLOUT;
    fds.push_back({c.fd, ev, 0});
    ids.push_back(id);
  }
  // A closing socket that cannot take its last bytes is closed after a grace period: wake for it.
  for (const auto& [id, c] : clients_)
    if (c.state == State::closing) timeout_ms = std::min(timeout_ms, 100);
  // And for a connection not yet upgraded that runs out of time.
  if (const double left = next_deadline(now_s()); left >= 0)
    timeout_ms = std::min(timeout_ms, int(std::ceil(left * 1000)));
  const int n = ::poll(fds.data(), nfds_t(fds.size()), timeout_ms);
  expire_slow(now_s());
  if (n < 0) return;  // EINTR: the host's loop calls again
  if (fds[0].revents & POLLIN) accept_all();
  for (size_t k = 1; k < fds.size(); ++k) {
    auto it = clients_.find(ids[k]);
    if (it == clients_.end()) continue;
    Client& c = it->second;
    const short re = fds[k].revents;
    if (re & (POLLIN | POLLHUP | POLLERR)) read_from(ids[k], c);
    it = clients_.find(ids[k]);
    if (it == clients_.end()) continue;
    if (!c.out.empty()) write_to(c);
    if (c.state == State::closing &&
        (c.out.empty() || now_s() - c.closing_since > kCloseGraceS || c.fd < 0))
      close_now(ids[k], c, "");
  }
}

void WsServer::accept_all() {
  for (;;) {
    sockaddr_in sa{};
    socklen_t len = sizeof sa;
    int fd =
        ::accept4(listen_fd_, reinterpret_cast<sockaddr*>(&sa), &len, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0 && (errno == EMFILE || errno == ENFILE)) {
      // No descriptor left (other files of the process, or the system's): take the connection
      // with the spare one, refuse it, and keep the spare for the next time.
      const std::string why = std::strerror(errno);
      if (spare_fd_ >= 0) {
        ::close(spare_fd_);
        fd = ::accept4(listen_fd_, reinterpret_cast<sockaddr*>(&sa), &len, SOCK_CLOEXEC);
        if (fd >= 0) refuse_now(fd, 503, "nsf serve: too many clients\n");
        spare_fd_ = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
      }
      emit("nsf serve: refused a connection: no file descriptor left (" + why + ")");
      if (fd < 0 || spare_fd_ < 0) accept_paused_until_ = now_s() + 0.1;  // do not spin on it
      return;
    }
    if (fd < 0) return;  // EAGAIN, or a connection that went away before we took it
    char ip[INET_ADDRSTRLEN] = "?";
    ::inet_ntop(AF_INET, &sa.sin_addr, ip, sizeof ip);
    const std::string peer = std::string(ip) + ":" + std::to_string(ntohs(sa.sin_port));
    if (clients_.size() >= options_.max_clients) {
      refuse_now(fd, 503, "nsf serve: too many clients\n");
      emit("nsf serve: refused " + peer + ": " + std::to_string(options_.max_clients) +
           " clients already (--max-clients)");
      continue;
    }
    size_t pending = 0;
    for (const auto& [id, c] : clients_) pending += c.state == State::http && c.ip == ip;
    if (pending >= options_.max_pending_per_address) {
      refuse_now(fd, 503, "nsf serve: too many connections from your address\n");
      emit("nsf serve: refused " + peer + ": " + std::to_string(pending) + " connections from " +
           ip + " not yet upgraded");
      continue;
    }
    const int one = 1;
    ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    Client c;
    c.fd = fd;
    c.peer = peer;
    c.ip = ip;
    c.connected = c.last_read = now_s();
    clients_.emplace(next_id_++, std::move(c));
  }
}

void WsServer::read_from(int id, Client& c) {
  char buf[16384];
  size_t total = 0;
  while (total < kReadPerPoll && (c.state == State::closing || !backed_up(c))) {
    const ssize_t r = ::recv(c.fd, buf, sizeof buf, MSG_DONTWAIT);
    if (r > 0) {
      if (c.state != State::closing) c.in.append(buf, size_t(r));
      total += size_t(r);
      c.last_read = now_s();
      if (c.state == State::http) handle_http(id, c);
      if (clients_.find(id) == clients_.end()) return;
      if (c.state == State::websocket) handle_frames(id, c);
      if (clients_.find(id) == clients_.end()) return;
      continue;
    }
    if (r < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return;
    if (r < 0 && errno == EINTR) continue;
    // 0: the peer closed; < 0: a reset. Either way it is gone.
    close_now(id, c, c.state == State::websocket ? "disconnected" : "");
    return;
  }
}

void WsServer::handle_http(int id, Client& c) {
  HttpRequest req;
  size_t used = 0;
  std::string why;
  const Parse p = parse_http_request(c.in, req, used, why);
  if (p == Parse::incomplete) {
    if (c.in.size() > options_.max_request)
      drop(id, c, 431,
           "an HTTP request head over " + std::to_string(options_.max_request) + " bytes");
    return;
  }
  if (p == Parse::error) return drop(id, c, 400, "a malformed HTTP request: " + why);
  // A head over the cap that arrived whole (in one read) is refused as one arriving piecemeal.
  if (used > options_.max_request)
    return drop(id, c, 431,
                "an HTTP request head over " + std::to_string(options_.max_request) + " bytes");
  c.in.erase(0, used);
  const bool wants_upgrade = !req.header("Upgrade").empty();
  if (const std::string refusal = origin_refusal(req, policy_, wants_upgrade); !refusal.empty())
    return drop(id, c, 403, refusal, "refused client");
  const auto answer = [&](std::string response) {
    enqueue(c, std::make_shared<const std::string>(std::move(response)));
  };
  if (!wants_upgrade) {
    c.state = State::closing;
    c.closing_since = now_s();
    c.in.clear();
    const std::string path = req.target.substr(0, req.target.find('?'));
    if (req.method != "GET" && req.method != "HEAD")
      answer(http_response(405, "Method Not Allowed", "text/plain", "GET only\n"));
    else if (path == "/" || path == "/index.html")
      answer(http_response(200, "OK", "text/html; charset=utf-8", page_));
    else
      answer(http_response(404, "Not Found", "text/plain", "not found\n"));
    return;
  }
  if (const std::string problem = upgrade_problem(req); !problem.empty())
    return drop(id, c, 400, "a bad WebSocket upgrade: " + problem);
  answer(upgrade_response(req));
  c.state = State::websocket;
  if (on_open) on_open(id);
}

void WsServer::handle_frames(int id, Client& c) {
  size_t at = 0;
  while (c.state == State::websocket) {
    const FrameParse f = parse_frame(reinterpret_cast<const uint8_t*>(c.in.data()) + at,
                                     c.in.size() - at, true, options_.max_message);
    if (f.status == Parse::incomplete) break;
    if (f.status == Parse::error) return drop(id, c, f.close_code, f.why);
    at += f.consumed;
    const Frame& fr = f.frame;
    if (fr.opcode == kPing) {
      // A pong counts against the caps like any frame: a client that pings faster than it reads
      // would otherwise make the server buffer without bound.
      Message pong = std::make_shared<const std::string>(encode_frame(kPong, fr.payload));
      if (!fits(c, pong->size()))
        return drop(id, c, kClosePolicy,
                    "pings faster than it reads (" + std::to_string(c.out.size()) + " messages, " +
                        std::to_string(c.out_bytes) + " bytes waiting for it: --queue)");
      enqueue(c, std::move(pong));
    } else if (fr.opcode == kPong) {
    } else if (fr.opcode == kClose) {
      enqueue(c, std::make_shared<const std::string>(
                     encode_frame(kClose, close_payload(kCloseNormal, ""))));
      c.state = State::closing;
      c.closing_since = now_s();
      emit("nsf serve: client " + std::to_string(id) + " (" + c.peer + ") closed" +
           (c.dropped ? ", " + std::to_string(c.dropped) + " messages dropped for it" : ""));
    } else if (!fr.fin || fr.opcode == kContinuation) {
      return drop(id, c, kCloseUnsupported, "a fragmented message (not accepted)");
    } else if (on_message) {
      const std::string why = on_message(id, fr.payload);
      if (!why.empty()) return drop(id, c, kClosePolicy, why);
    }
  }
  c.in.erase(0, at);
}

void WsServer::write_to(Client& c) {
  while (!c.out.empty()) {
    const std::string& m = *c.out.front().m;
    const ssize_t w =
        ::send(c.fd, m.data() + c.out_offset, m.size() - c.out_offset, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (w < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return;
      c.out.clear();  // a broken socket: the next read sees it go
      c.out_bytes = 0;
      c.state = State::closing;
      return;
    }
    c.out_offset += size_t(w);
    if (c.out_offset < m.size()) return;
    c.out_bytes -= c.out.front().counted;
    c.out.pop_front();
    c.out_offset = 0;
  }
}

double WsServer::next_deadline(double now) const {
  double left = -1;
  for (const auto& [id, c] : clients_) {
    if (c.state != State::http) continue;
    const double t = std::max(0.0, std::min(c.connected + options_.header_timeout_s,
                                            c.last_read + options_.idle_timeout_s) -
                                       now);
    left = left < 0 ? t : std::min(left, t);
  }
  return left;
}

void WsServer::expire_slow(double now) {
  for (auto& [id, c] : clients_) {
    if (c.state != State::http) continue;
    if (now >= c.connected + options_.header_timeout_s)
      drop(id, c, 408,
           "no complete request head within " + seconds(options_.header_timeout_s) +
               " of connecting");
    else if (now >= c.last_read + options_.idle_timeout_s)
      drop(id, c, 408,
           "nothing received for " + seconds(options_.idle_timeout_s) +
               " before its request was complete");
  }
}

void WsServer::drop(int id, Client& c, uint16_t code, const std::string& why, const char* verb) {
  ++malformed_;
  emit("nsf serve: " + std::string(verb) + " " + std::to_string(id) + " (" + c.peer + "): " + why);
  // Whatever was queued for it goes unsent, except the part of a message already on the wire.
  while (c.out.size() > (c.out_offset ? 1u : 0u)) {
    c.out_bytes -= c.out.back().counted;
    c.out.pop_back();
  }
  if (c.state == State::websocket)
    enqueue(c, std::make_shared<const std::string>(encode_frame(kClose, close_payload(code, why))));
  else
    enqueue(c, std::make_shared<const std::string>(
                   http_response(code, reason_phrase(code), "text/plain", log_safe(why) + "\n")));
  c.state = State::closing;
  c.closing_since = now_s();
  c.in.clear();
  write_to(c);
}

void WsServer::close_now(int id, Client& c, const std::string& why) {
  if (!why.empty())
    emit("nsf serve: client " + std::to_string(id) + " (" + c.peer + ") " + why +
         (c.dropped ? ", " + std::to_string(c.dropped) + " messages dropped for it" : ""));
  ::close(c.fd);
  clients_.erase(id);
}

}  // namespace nsf::net
