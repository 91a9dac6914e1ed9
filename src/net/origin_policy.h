#pragma once
// Which requests a server on a local address may serve (docs/SERVE.md, "Who may connect"). Any web
// page open in the user's browser can make it connect to 127.0.0.1; the browser says which page
// asks (Origin) and which name it used for the server (Host). A WebSocket is opened only for the
// server's own page (Origin = http:// + the request's Host) or an origin allowed by name, and only
// when Host names this server (not a name an attacker's DNS points at it: DNS rebinding).
// A request without Origin or Host comes from a program, not a page (browsers always send both):
// it is served.
#include <string>
#include <vector>

#include "net/websocket.h"

namespace nsf::net {

struct OriginPolicy {
  std::string bind;  // the IPv4 address listened on
  int port = 0;      // the port listened on
  // Host names accepted besides the bound address (with any port); "*": any Host. Bound to
  // loopback, localhost, 127.0.0.1 and [::1] are accepted; bound to 0.0.0.0, localhost and any IP
  // literal; each with the server's port.
  std::vector<std::string> allow_hosts;
  // Origins accepted besides the server's own, exactly as a browser sends them
  // ("http://example.org:8000"); "*": any.
  std::vector<std::string> allow_origins;
};

// "" when `r` may be served (`upgrade`: it asks for a WebSocket, so its Origin counts); else why
// not, for a 403 and a log line.
std::string origin_refusal(const HttpRequest& r, const OriginPolicy& p, bool upgrade);

}  // namespace nsf::net
