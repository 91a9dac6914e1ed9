// Who may connect to `nsf serve` (src/net/origin_policy.h) and what a log line may hold of a
// client's text (src/net/log_text.h), without sockets.
#include <gtest/gtest.h>

#include "net/log_text.h"
#include "net/origin_policy.h"

namespace {

using nsf::net::HttpRequest;
using nsf::net::log_safe;
using nsf::net::origin_refusal;
using nsf::net::OriginPolicy;

HttpRequest request(const std::string& host, const std::string& origin) {
  HttpRequest r;
  r.method = "GET";
  r.target = "/stream";
  r.version = "HTTP/1.1";
  if (!host.empty()) r.headers.emplace_back("Host", host);
  if (!origin.empty()) r.headers.emplace_back("Origin", origin);
  return r;
}

bool allowed(const OriginPolicy& p, const std::string& host, const std::string& origin) {
  return origin_refusal(request(host, origin), p, true).empty();
}

TEST(NetOrigin, OnLoopbackOnlyTheServersOwnNamesAndPage) {
  OriginPolicy p;
  p.bind = "127.0.0.1";
  p.port = 8080;
  for (const char* host : {"127.0.0.1:8080", "localhost:8080", "LocalHost:8080", "[::1]:8080"})
    EXPECT_TRUE(allowed(p, host, "")) << host;
  for (const char* host :
       {"127.0.0.1", "localhost:80", "127.0.0.1:8081", "evil.example.com:8080", "192.168.1.2:8080",
        "127.0.0.1:", "127.0.0.1:x", "127.0.0.1:99999", ":8080", "[::1", "localhost.:8080"})
    EXPECT_FALSE(allowed(p, host, "")) << host;
  EXPECT_TRUE(allowed(p, "", ""));  // a program that sends neither
  EXPECT_TRUE(allowed(p, "localhost:8080", "http://localhost:8080"));
  EXPECT_TRUE(allowed(p, "localhost:8080", "HTTP://LOCALHOST:8080"));
  EXPECT_FALSE(allowed(p, "localhost:8080", "http://127.0.0.1:8080"));
  EXPECT_FALSE(allowed(p, "localhost:8080", "https://localhost:8080"));
  EXPECT_FALSE(allowed(p, "localhost:8080", "http://localhost:8080/x"));
  EXPECT_FALSE(allowed(p, "localhost:8080", "http://evil.example.com"));
  EXPECT_FALSE(allowed(p, "localhost:8080", "null"));
  EXPECT_FALSE(allowed(p, "", "http://localhost:8080"));  // a browser always sends Host
  // The page itself (no upgrade): only Host counts.
  EXPECT_TRUE(
      origin_refusal(request("localhost:8080", "http://evil.example.com"), p, false).empty());
  EXPECT_FALSE(origin_refusal(request("evil.example.com:8080", ""), p, false).empty());
  // The reason says which header and how to widen it.
  EXPECT_NE(origin_refusal(request("localhost:8080", "http://evil.example.com"), p, true)
                .find("Origin 'http://evil.example.com'"),
            std::string::npos);
}

TEST(NetOrigin, OnEveryInterfaceAnyIpLiteralAndAllowedNames) {
  OriginPolicy p;
  p.bind = "0.0.0.0";
  p.port = 80;
  for (const char* host : {"192.168.1.20", "10.0.0.1:80", "localhost", "[fe80::1]", "[::1]:80"})
    EXPECT_TRUE(allowed(p, host, "")) << host;
  for (const char* host : {"myhost.lan", "evil.example.com", "192.168.1.20:81", "[nothex]"})
    EXPECT_FALSE(allowed(p, host, "")) << host;
  EXPECT_TRUE(allowed(p, "192.168.1.20", "http://192.168.1.20"));
  EXPECT_TRUE(allowed(p, "192.168.1.20", "http://192.168.1.20:80"));
  EXPECT_FALSE(allowed(p, "127.0.0.1", "http://192.168.1.20"));  // another site's page
  p.allow_hosts = {"myhost.lan"};
  p.allow_origins = {"http://app.example.org"};
  EXPECT_TRUE(allowed(p, "myhost.lan:8443", "http://myhost.lan:8443"));
  EXPECT_TRUE(allowed(p, "myhost.lan", "http://app.example.org"));
  EXPECT_FALSE(allowed(p, "myhost.lan", "http://evil.example.com"));
  p.allow_hosts = {"*"};
  p.allow_origins = {"*"};
  EXPECT_TRUE(allowed(p, "evil.example.com", "http://evil.example.com:1"));
}

TEST(NetLogText, ControlCharactersAndBadUtf8AreEscaped) {
  EXPECT_EQ(log_safe("plain text, ünïcødé ẑ €"), "plain text, ünïcødé ẑ €");
  EXPECT_EQ(log_safe("\n\x1b[31mnsf serve: FAKE"), "\\x0a\\x1b[31mnsf serve: FAKE");
  EXPECT_EQ(log_safe(std::string("a\0b\x7f\\", 5)), "a\\x00b\\x7f\\\\");
  EXPECT_EQ(log_safe("\xff\xfe"), "\\xff\\xfe");
  EXPECT_EQ(log_safe("\xc2\x9b"
                     "31m"),
            "\\u009b31m");                                          // C1 CSI
  EXPECT_EQ(log_safe("\xc0\xaf"), "\\xc0\\xaf");                    // overlong '/'
  EXPECT_EQ(log_safe("\xed\xa0\x80"), "\\xed\\xa0\\x80");           // a surrogate
  EXPECT_EQ(log_safe("\xf4\x90\x80\x80"), "\\xf4\\x90\\x80\\x80");  // past U+10FFFF
  EXPECT_EQ(log_safe("\xe2\x82"), "\\xe2\\x82");                    // cut short
  EXPECT_EQ(log_safe(std::string(100, 'x'), 10), std::string(10, 'x') + "...(100 bytes)");
  EXPECT_EQ(log_safe(std::string(10, 'x'), 10), std::string(10, 'x'));
}

}  // namespace
