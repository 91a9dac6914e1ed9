// A load test of a running `nsf serve` (docs/BENCHMARKS.md, "The latent stream"), left out of the
// suite (DISABLED_): N clients on loopback for S seconds, counting the frames each receives, the
// frames lost (gaps in the frame numbers) and the latency from the server's step to the client.
//   build/nsf serve MODEL SCENE --port 8765 &   (NSF_LOAD_WARMUP: seconds before latency counts, 5)
//   NSF_SERVE_PORT=8765 NSF_LOAD_CLIENTS=50 NSF_LOAD_SECONDS=60 build/nsf_tests
//       --gtest_also_run_disabled_tests --gtest_filter='ServeLoad.*'   (one command line)
#include <gtest/gtest.h>
#include <poll.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <memory>

#include "ws_client.h"

namespace {

double env(const char* name, double fallback) {
  const char* v = std::getenv(name);
  return v ? std::atof(v) : fallback;
}

double wall_now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

TEST(ServeLoad, DISABLED_ManyClientsOnLoopback) {
  const int port = int(env("NSF_SERVE_PORT", 8080));
  const int n = int(env("NSF_LOAD_CLIENTS", 20));
  const double seconds = env("NSF_LOAD_SECONDS", 20);
  // Latency counts from here on: first every client takes the model message (megabytes for a
  // paper-size scene), and the frames queued behind it arrive late.
  const double warmup = env("NSF_LOAD_WARMUP", 5);
  std::vector<std::unique_ptr<nsf::testing::WsClient>> clients;
  for (int i = 0; i < n; ++i) {
    clients.push_back(std::make_unique<nsf::testing::WsClient>());
    ASSERT_TRUE(clients.back()->connect(port)) << "client " << i << " on port " << port;
  }
  std::vector<long> received(size_t(n), 0), lost(size_t(n), 0), last(size_t(n), -1);
  std::vector<double> latency;
  const double start = wall_now(), end = start + seconds;
  size_t ended = 0;  // clients whose server went away (a run with --frames ending first)
  while (wall_now() < end && ended < clients.size()) {
    std::vector<pollfd> fds;
    for (auto& c : clients) fds.push_back({c->eof() ? -1 : c->fd(), POLLIN, 0});
    ::poll(fds.data(), fds.size(), 100);
    const double now = wall_now();
    for (size_t i = 0; i < clients.size(); ++i) {
      if (!(fds[i].revents & POLLIN)) continue;
      for (const nsf::net::Frame& f : clients[i]->drain()) {
        if (f.payload.size() < 24 || f.payload.compare(0, 4, "NSFF") != 0) continue;
        uint32_t frame;
        double sent;
        std::memcpy(&frame, f.payload.data() + 4, 4);
        std::memcpy(&sent, f.payload.data() + 16, 8);
        if (last[i] >= 0 && long(frame) > last[i] + 1) lost[i] += long(frame) - last[i] - 1;
        last[i] = frame;
        ++received[i];
        if (now - start >= warmup) latency.push_back(now - sent);
      }
      ended += clients[i]->eof();
    }
  }
  std::sort(latency.begin(), latency.end());
  const auto q = [&](double p) {
    return latency.empty() ? 0.0 : 1e3 * latency[size_t(p * double(latency.size() - 1))];
  };
  long total_lost = 0;
  for (long l : lost) total_lost += l;
  std::printf(
      "%d clients, %.0f s: frames received per client %ld to %ld, frames lost %ld; latency "
      "step to client after %.0f s: median %.2f ms, p99 %.2f ms, max %.2f ms; %zu saw the server "
      "stop\n",
      n, seconds, *std::min_element(received.begin(), received.end()),
      *std::max_element(received.begin(), received.end()), total_lost, warmup, q(0.5), q(0.99),
      q(1.0), ended);
  EXPECT_EQ(total_lost, 0);
}

}  // namespace
