// The clients of bench/serve_load.sh (docs/BENCHMARKS.md, "The latent stream"): N WebSocket
// clients of a running `nsf serve` on loopback for S seconds, counting the frames each receives,
// the frames lost (gaps in the frame numbers), the latency from the server's step to the client,
// and how long after connecting each had its first frame and the whole basis. --read-rate reads
// at most that many bytes a second per client, as over a slower link. Exits 1 when a frame was
// lost or a client could not connect.
//   build/nsf serve MODEL SCENE --port 8765 &
//   build/serve_clients --port 8765 --clients 50 --seconds 60 [--warmup 5] [--read-rate 2e6]
#include <poll.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "ws_client.h"

namespace {

double wall_now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

struct Load {
  int port = 8080;
  int clients = 20;
  double seconds = 20;
  // Latency counts from here on: first every client takes the model message (megabytes for a
  // paper-size scene), and the frames queued behind it arrive late.
  double warmup = 5;
  double read_rate = 0;  // bytes a second per client; 0: as fast as it comes
};

// When a client had its first frame and the whole basis (the model message's modes and the
// basis messages' after it), in seconds after it connected; < 0: not yet.
struct Arrival {
  double connected = 0, first_frame = -1, basis = -1;
  long modes = 0, received = 0;  // the model's modes, and those received
  void on_message(const std::string& m, double now) {
    if (m.compare(0, 4, "NSFM") == 0 && m.size() >= 8) {
      uint32_t h = 0;
      std::memcpy(&h, m.data() + 4, 4);
      const auto j = nlohmann::json::parse(m.substr(8, h), nullptr, false);
      if (j.is_discarded()) return;
      modes = j.value("modes", 0L);
      received = j.value("modes_here", modes);
    } else if (m.compare(0, 4, "NSFB") == 0 && m.size() >= 12) {
      uint32_t n = 0;  // the message's modes (docs/SERVE.md, "Basis messages")
      std::memcpy(&n, m.data() + 8, 4);
      received += long(n);
    } else if (m.compare(0, 4, "NSFF") == 0 && first_frame < 0) {
      first_frame = now - connected;
    }
    if (basis < 0 && modes > 0 && received == modes) basis = now - connected;
  }
};

// "median M ms, max X ms" of the non-negative values (and how many were not reached).
std::string spread(std::vector<double> v) {
  const size_t missing = size_t(std::count_if(v.begin(), v.end(), [](double x) { return x < 0; }));
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return x < 0; }), v.end());
  if (v.empty()) return "never";
  std::sort(v.begin(), v.end());
  char b[128];
  std::snprintf(b, sizeof b, "median %.0f ms, max %.0f ms", 1e3 * v[v.size() / 2], 1e3 * v.back());
  return std::string(b) + (missing ? " (" + std::to_string(missing) + " never)" : "");
}

int run(const Load& load) {
  const int n = load.clients;
  const double seconds = load.seconds, warmup = load.warmup;
  std::vector<std::unique_ptr<nsf::testing::WsClient>> clients;
  std::vector<Arrival> arrival(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    clients.push_back(std::make_unique<nsf::testing::WsClient>());
    arrival[size_t(i)].connected = wall_now();
    if (!clients.back()->connect(load.port)) {
      std::fprintf(stderr, "serve_clients: client %d cannot connect to port %d\n", i, load.port);
      return 1;
    }
  }
  std::vector<long> received(size_t(n), 0), lost(size_t(n), 0), last(size_t(n), -1);
  std::vector<double> latency;
  const double start = wall_now(), end = start + seconds;
  size_t ended = 0;  // clients whose server went away (a run with --frames ending first)
  while (wall_now() < end && ended < clients.size()) {
    std::vector<pollfd> fds;
    for (auto& c : clients) fds.push_back({c->eof() ? -1 : c->fd(), POLLIN, 0});
    // A client that reads slowly leaves its data waiting: poll() would not wait at all.
    if (load.read_rate > 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    ::poll(fds.data(), fds.size(), 100);
    const double now = wall_now();
    for (size_t i = 0; i < clients.size(); ++i) {
      if (!(fds[i].revents & POLLIN)) continue;
      const double allowed = load.read_rate * (now - arrival[i].connected);
      const size_t budget = load.read_rate <= 0
                                ? SIZE_MAX
                                : size_t(std::max(0.0, allowed - double(clients[i]->bytes_read())));
      for (const nsf::net::Frame& f : clients[i]->drain(budget)) {
        arrival[i].on_message(f.payload, now);
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
  std::vector<double> first, whole;
  for (const Arrival& a : arrival) {
    first.push_back(a.first_frame);
    whole.push_back(a.basis);
  }
  std::printf("first frame after connecting: %s; the whole basis: %s\n", spread(first).c_str(),
              spread(whole).c_str());
  std::printf(
      "%d clients, %.0f s: frames received per client %ld to %ld, frames lost %ld; latency "
      "step to client after %.0f s: median %.2f ms, p99 %.2f ms, max %.2f ms; %zu saw the server "
      "stop\n",
      n, seconds, *std::min_element(received.begin(), received.end()),
      *std::max_element(received.begin(), received.end()), total_lost, warmup, q(0.5), q(0.99),
      q(1.0), ended);
  return total_lost == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  Load load;
  CLI::App app{"N WebSocket clients of a running nsf serve on loopback: frames, losses, latency"};
  app.add_option("--port", load.port, "the server's port")->check(CLI::Range(1, 65535));
  app.add_option("--clients", load.clients, "clients")->check(CLI::Range(1, 100000));
  app.add_option("--seconds", load.seconds, "how long they listen")->check(CLI::Range(0.1, 1e6));
  app.add_option("--warmup", load.warmup, "seconds before latency counts")
      ->check(CLI::Range(0.0, 1e6));
  app.add_option("--read-rate", load.read_rate,
                 "bytes a second each client reads at most (a slower link); 0: no limit")
      ->check(CLI::Range(0.0, 1e12));
  CLI11_PARSE(app, argc, argv);
  return run(load);
}
