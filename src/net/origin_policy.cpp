#include "net/origin_policy.h"

#include <arpa/inet.h>

#include <algorithm>
#include <cctype>
#include <optional>

namespace nsf::net {

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

struct Authority {
  std::string host;  // lower case; an IPv6 literal keeps its brackets
  int port = 80;     // http's when none is written
};

// "name", "name:port", "[v6]" or "[v6]:port"; nullopt when it is none of these.
std::optional<Authority> parse_authority(const std::string& s) {
  Authority a;
  size_t host_end;
  if (!s.empty() && s[0] == '[') {
    host_end = s.find(']');
    if (host_end == std::string::npos) return std::nullopt;
    ++host_end;
  } else {
    host_end = std::min(s.find(':'), s.size());
  }
  a.host = lower(s.substr(0, host_end));
  if (a.host.empty()) return std::nullopt;
  if (host_end < s.size()) {
    const std::string port = s.substr(host_end + 1);
    if (s[host_end] != ':' || port.empty() || port.size() > 5 ||
        !std::all_of(port.begin(), port.end(), [](char c) { return c >= '0' && c <= '9'; }))
      return std::nullopt;
    a.port = std::stoi(port);
    if (a.port < 1 || a.port > 65535) return std::nullopt;
  }
  return a;
}

bool listed(const std::vector<std::string>& list, const std::string& value) {
  for (const std::string& v : list)
    if (v == "*" || lower(v) == lower(value)) return true;
  return false;
}

bool ip_literal(const std::string& host) {
  unsigned char buf[16];
  if (::inet_pton(AF_INET, host.c_str(), buf) == 1) return true;
  return host.size() > 2 && host.front() == '[' && host.back() == ']' &&
         ::inet_pton(AF_INET6, host.substr(1, host.size() - 2).c_str(), buf) == 1;
}

// Whether a browser that wrote `a` in its address bar reached this server.
bool names_this_server(const Authority& a, const OriginPolicy& p) {
  if (listed(p.allow_hosts, a.host)) return true;
  if (a.port != p.port) return false;
  if (a.host == p.bind) return true;
  if (p.bind.rfind("127.", 0) == 0)
    return a.host == "localhost" || a.host == "127.0.0.1" || a.host == "[::1]";
  if (p.bind == "0.0.0.0") return a.host == "localhost" || ip_literal(a.host);
  return false;
}

}  // namespace

std::string origin_refusal(const HttpRequest& r, const OriginPolicy& p, bool upgrade) {
  const std::string host = r.header("Host"), origin = r.header("Origin");
  std::optional<Authority> h;
  if (!host.empty()) {
    h = parse_authority(host);
    if (!h || !names_this_server(*h, p))
      return "Host '" + host + "' does not name this server (--allow-host adds a name)";
  }
  if (!upgrade || origin.empty() || listed(p.allow_origins, origin)) return "";
  const std::string scheme = "http://";
  if (lower(origin.substr(0, scheme.size())) == scheme && h) {
    const auto o = parse_authority(origin.substr(scheme.size()));
    if (o && o->host == h->host && o->port == h->port) return "";
  }
  return "Origin '" + origin + "' is not this server's page (--allow-origin allows it)";
}

}  // namespace nsf::net
