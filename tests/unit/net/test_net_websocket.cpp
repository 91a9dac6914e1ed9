// RFC test vectors for the WebSocket pieces of `nsf serve` (src/net/): SHA-1, base64, the
// handshake's accept key, the frames of RFC 6455 §5.7, and the parser's refusals.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "net/base64.h"
#include "net/sha1.h"
#include "net/websocket.h"

namespace {

using namespace nsf::net;

std::string hex(const std::array<uint8_t, 20>& d) {
  std::string out;
  char b[3];
  for (uint8_t x : d) {
    std::snprintf(b, sizeof b, "%02x", x);
    out += b;
  }
  return out;
}

std::string bytes(std::initializer_list<int> v) {
  std::string s;
  for (int x : v) s += char(x);
  return s;
}

FrameParse parse(const std::string& s, bool masked, size_t max = 1 << 20) {
  return parse_frame(reinterpret_cast<const uint8_t*>(s.data()), s.size(), masked, max);
}

TEST(NetSha1, Fips180Vectors) {
  EXPECT_EQ(hex(sha1("abc")), "a9993e364706816aba3e25717850c26c9cd0d89d");
  EXPECT_EQ(hex(sha1("")), "da39a3ee5e6b4b0d3255bfef95601890afd80709");
  EXPECT_EQ(hex(sha1("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq")),
            "84983e441c3bd26ebaae4aa1f95129e5e54670f1");
  EXPECT_EQ(hex(sha1(std::string(1000000, 'a'))), "34aa973cd4c4daa4f61eeb2bdbad27316534016f");
  // The padding's edge cases: 55, 56 and 64 bytes (one block, two blocks).
  EXPECT_EQ(hex(sha1(std::string(55, 'a'))), "c1c8bbdc22796e28c0e15163d20899b65621d65a");
  EXPECT_EQ(hex(sha1(std::string(56, 'a'))), "c2db330f6083854c99d4b5bfb6e8f29f201be699");
  EXPECT_EQ(hex(sha1(std::string(64, 'a'))), "0098ba824b5c16427bd7a1122a5a442a25ec644d");
}

TEST(NetBase64, Rfc4648Vectors) {
  const std::vector<std::pair<std::string, std::string>> v = {{"", ""},
                                                              {"f", "Zg=="},
                                                              {"fo", "Zm8="},
                                                              {"foo", "Zm9v"},
                                                              {"foob", "Zm9vYg=="},
                                                              {"fooba", "Zm9vYmE="},
                                                              {"foobar", "Zm9vYmFy"}};
  for (const auto& [plain, coded] : v) {
    EXPECT_EQ(base64_encode(plain.data(), plain.size()), coded);
    EXPECT_EQ(base64_decode(coded), plain) << coded;
  }
  for (const char* bad : {"Zm9", "Zg=a", "Z===", "Zm9v!A==", "Zg==Zg==", "=Zg="})
    EXPECT_FALSE(base64_decode(bad)) << bad;
}

TEST(NetHandshake, Rfc6455AcceptKey) {
  // RFC 6455 §1.3.
  EXPECT_EQ(websocket_accept("dGhlIHNhbXBsZSBub25jZQ=="), "s3pPLMBiTxaQ9kYGzzhZRbK+xOo=");
}

TEST(NetHandshake, ParsesAndChecksTheUpgradeRequest) {
  const std::string req =
      "GET /chat HTTP/1.1\r\nHost: server.example.com\r\nUpgrade: websocket\r\n"
      "Connection: keep-alive, Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
      "Origin: http://example.com\r\nSec-WebSocket-Version: 13\r\n\r\nextra";
  HttpRequest r;
  size_t used = 0;
  std::string why;
  for (size_t n = 0; n + 5 < req.size(); ++n)  // every prefix short of the blank line waits
    EXPECT_EQ(parse_http_request(req.substr(0, n), r, used, why), Parse::incomplete) << n;
  ASSERT_EQ(parse_http_request(req, r, used, why), Parse::done);
  EXPECT_EQ(used, req.size() - 5);
  EXPECT_EQ(r.target, "/chat");
  EXPECT_EQ(r.header("sec-websocket-version"), "13");
  EXPECT_EQ(upgrade_problem(r), "");
  EXPECT_NE(upgrade_response(r).find("Sec-WebSocket-Accept: s3pPLMBiTxaQ9kYGzzhZRbK+xOo=\r\n"),
            std::string::npos);

  auto problem = [&](const std::string& from, const std::string& to) {
    std::string s = req;
    s.replace(s.find(from), from.size(), to);
    HttpRequest q;
    if (parse_http_request(s, q, used, why) != Parse::done) return std::string("unparsed");
    return upgrade_problem(q);
  };
  EXPECT_NE(problem("GET", "POST"), "");
  EXPECT_NE(problem("HTTP/1.1", "HTTP/1.0"), "");
  EXPECT_NE(problem("Upgrade: websocket", "Upgrade: h2c"), "");
  EXPECT_NE(problem("keep-alive, Upgrade", "keep-alive"), "");
  EXPECT_NE(problem("Version: 13", "Version: 8"), "");
  EXPECT_NE(problem("dGhlIHNhbXBsZSBub25jZQ==", "c2hvcnQ="), "");  // 5 bytes, not 16
  EXPECT_EQ(parse_http_request("GARBAGE\r\n\r\n", r, used, why), Parse::error);
  EXPECT_EQ(parse_http_request("GET / HTTP/1.1\r\nno colon\r\n\r\n", r, used, why), Parse::error);
  EXPECT_EQ(parse_http_request(std::string("GET / HTTP/1.1\r\nA: \x01\r\n\r\n"), r, used, why),
            Parse::error);
}

TEST(NetFrames, Rfc6455Examples) {
  // §5.7: a single-frame unmasked text message, and the same masked.
  const std::string hello = bytes({0x81, 0x05, 0x48, 0x65, 0x6c, 0x6c, 0x6f});
  const std::string masked =
      bytes({0x81, 0x85, 0x37, 0xfa, 0x21, 0x3d, 0x7f, 0x9f, 0x4d, 0x51, 0x58});
  EXPECT_EQ(encode_frame(kText, "Hello"), hello);
  const uint8_t mask[4] = {0x37, 0xfa, 0x21, 0x3d};
  EXPECT_EQ(encode_frame(kText, "Hello", mask), masked);
  FrameParse f = parse(hello, false);
  ASSERT_EQ(f.status, Parse::done);
  EXPECT_EQ(f.frame.payload, "Hello");
  EXPECT_EQ(f.consumed, hello.size());
  f = parse(masked, true);
  ASSERT_EQ(f.status, Parse::done);
  EXPECT_EQ(f.frame.payload, "Hello");
  EXPECT_TRUE(f.frame.fin);
  // A fragmented unmasked text message: "Hel", then "lo".
  f = parse(bytes({0x01, 0x03, 0x48, 0x65, 0x6c}), false);
  ASSERT_EQ(f.status, Parse::done);
  EXPECT_FALSE(f.frame.fin);
  EXPECT_EQ(f.frame.opcode, kText);
  f = parse(bytes({0x80, 0x02, 0x6c, 0x6f}), false);
  EXPECT_TRUE(f.frame.fin);
  EXPECT_EQ(f.frame.opcode, kContinuation);
  // Ping with "Hello".
  f = parse(bytes({0x89, 0x05, 0x48, 0x65, 0x6c, 0x6c, 0x6f}), false);
  EXPECT_EQ(f.frame.opcode, kPing);
  // 256 bytes and 64 KiB binary messages: 16- and 64-bit lengths.
  EXPECT_EQ(encode_frame(kBinary, std::string(256, 'x')).substr(0, 4), bytes({0x82, 0x7E, 1, 0}));
  EXPECT_EQ(encode_frame(kBinary, std::string(65536, 'x')).substr(0, 10),
            bytes({0x82, 0x7F, 0, 0, 0, 0, 0, 1, 0, 0}));
  for (size_t n : {0, 125, 126, 65535, 65536, 70000}) {
    const std::string p(n, 'q');
    const uint8_t m[4] = {1, 2, 3, 4};
    const FrameParse g = parse(encode_frame(kBinary, p, m), true);
    ASSERT_EQ(g.status, Parse::done) << n;
    EXPECT_EQ(g.frame.payload, p);
  }
}

TEST(NetFrames, EveryPrefixIsIncomplete) {
  const uint8_t m[4] = {9, 8, 7, 6};
  for (size_t n : {5, 300, 70000}) {
    const std::string f = encode_frame(kBinary, std::string(n, 'z'), m);
    for (size_t k = 0; k < f.size(); k += (k < 20 ? 1 : 997))
      EXPECT_EQ(parse(f.substr(0, k), true).status, Parse::incomplete) << n << " " << k;
  }
}

TEST(NetFrames, RefusesWhatTheRfcForbidsAndOversizedFrames) {
  const uint8_t m[4] = {1, 2, 3, 4};
  auto code = [&](const std::string& s, bool masked, size_t max = 1 << 20) {
    const FrameParse f = parse(s, masked, max);
    return f.status == Parse::error ? int(f.close_code) : -int(f.status);
  };
  EXPECT_EQ(code(encode_frame(kText, "hi"), true), kCloseProtocol);        // unmasked to a server
  EXPECT_EQ(code(encode_frame(kText, "hi", m), false), kCloseProtocol);    // masked to a client
  EXPECT_EQ(code(bytes({0xC1, 0x80, 1, 2, 3, 4}), true), kCloseProtocol);  // RSV1
  EXPECT_EQ(code(bytes({0x83, 0x80, 1, 2, 3, 4}), true), kCloseProtocol);  // opcode 3
  EXPECT_EQ(code(bytes({0x8B, 0x80, 1, 2, 3, 4}), true), kCloseProtocol);  // opcode 0xB
  EXPECT_EQ(code(bytes({0x09, 0x80, 1, 2, 3, 4}), true), kCloseProtocol);  // fragmented ping
  EXPECT_EQ(code(encode_frame(kPing, std::string(126, 'p'), m), true), kCloseProtocol);
  EXPECT_EQ(code(bytes({0x82, 0xFF, 0x80, 0, 0, 0, 0, 0, 0, 0}), true), kCloseProtocol);
  // Oversized: refused from the length alone, before the payload arrives.
  EXPECT_EQ(code(bytes({0x82, 0xFE, 0x10, 0x00}), true, 4095), kCloseTooBig);
  EXPECT_EQ(code(bytes({0x82, 0xFF, 0, 0, 0, 1, 0, 0, 0, 0}), true, 4096), kCloseTooBig);
  EXPECT_EQ(code(encode_frame(kText, std::string(4096, 'a'), m), true, 4096), -int(Parse::done));
  EXPECT_EQ(close_payload(1009, "big"), bytes({0x03, 0xF1, 'b', 'i', 'g'}));
  EXPECT_EQ(close_payload(1000, std::string(500, 'r')).size(), 125u);
}

}  // namespace

namespace {

// A bounded fuzz of the parsers alone: 100,000 random and mutated frames and 20,000 mutated
// request heads. Nothing may crash (a crash fails the suite), and every answer must hold together.
TEST(NetFrames, BoundedFuzzOfTheParsers) {
  std::mt19937 rng(6455);
  const uint8_t mask[4] = {0xA1, 0xB2, 0xC3, 0xD4};
  const size_t max = 512;
  int done = 0, errors = 0;
  for (int k = 0; k < 100000; ++k) {
    std::string f;
    if (k % 2) {
      for (int i = int(rng() % 40); i > 0; --i) f += char(rng());
    } else {
      f = encode_frame(uint8_t(rng() % 16), std::string(rng() % 700, 'x'),
                       rng() % 8 ? mask : nullptr, rng() % 4);
      for (int i = int(rng() % 4); i > 0; --i) f[rng() % f.size()] = char(rng());
      if (rng() % 2) f.resize(rng() % (f.size() + 1));
    }
    const FrameParse p = parse(f, true, max);
    if (p.status == Parse::done) {
      ++done;
      ASSERT_LE(p.consumed, f.size());
      ASSERT_LE(p.frame.payload.size(), max);
    } else if (p.status == Parse::error) {
      ++errors;
      ASSERT_TRUE(p.close_code == kCloseProtocol || p.close_code == kCloseTooBig) << p.close_code;
      ASSERT_FALSE(p.why.empty());
    }
  }
  EXPECT_GT(done, 1000);
  EXPECT_GT(errors, 1000);
  const std::string head =
      "GET / HTTP/1.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
      "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n";
  for (int k = 0; k < 20000; ++k) {
    std::string h = head;
    for (int i = int(rng() % 6); i > 0; --i) h[rng() % h.size()] = char(rng());
    h.resize(rng() % (h.size() + 1));
    HttpRequest r;
    size_t used = 0;
    std::string why;
    if (parse_http_request(h, r, used, why) == Parse::done) {
      ASSERT_LE(used, h.size());
      upgrade_problem(r);  // must not throw
    }
  }
}

}  // namespace
