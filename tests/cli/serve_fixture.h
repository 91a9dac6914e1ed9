#pragma once
// `nsf serve` as a child process on a tiny basis model of scenes/examples/rom_tiny.json (trained
// once per test process, in SetUpTestSuite), on an ephemeral port: the fixture of the end-to-end
// tests (test_app_serve.cpp, test_app_serve_hostile.cpp), and the reading of its stream.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "app/serve_protocol.h"
#include "cli_child.h"
#include "data/sweep.h"
#include "nn/torch_settings.h"
#include "nn/train/trainer.h"
#include "ws_client.h"

namespace nsf::testing::serve {

namespace fs = std::filesystem;
using nsf::app::decode_frame;
using nsf::app::StreamFrame;

inline const std::string kScene =
    (fs::path(NSF_SOURCE_DIR) / "scenes" / "examples" / "rom_tiny.json").string();

class ServeEndToEnd : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    nsf::set_nn_threads(2);
    root_ = fs::temp_directory_path() / ("nsf_serve_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    nsf::SweepOptions so;
    so.out_dir = (root_ / "data").string();
    so.jobs = 2;
    so.quiet = true;
    nsf::run_sweep(kScene, so);
    nsf::TrainOptions o;
    nsf::TrainConfig& c = o.config;
    c.net.decoder = nsf::DecoderFamily::basis;
    c.net.latent_dim = 3;
    c.net.depth = 2;
    c.net.width_g = c.net.width_h = c.net.width_l = 16;
    c.net.encoder_hidden = 8;
    c.net.modes = {8, 8, 8};
    c.net.coefficient_width = 16;
    c.net.coefficient_depth = 2;
    c.steps = {300, 100, 100};
    c.frames_per_batch = {4, 16, 16};
    c.particles_per_frame = {128, 128, 128};
    c.seed = 3;
    c.quiet = true;
    nsf::train_model((root_ / "data").string(), model(), o);
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }
  static std::string model() { return (root_ / "tiny_basis.nsf").string(); }

  // Starts `nsf serve` on an ephemeral port; returns the port (0 if it never said which).
  // `in_child` runs in the server's process before exec (setrlimit).
  int start(const std::vector<std::string>& extra, const std::string& scene = kScene,
            const std::function<void()>& in_child = {}) {
    // A log of its own: reading another test's log would find that server's (dead) port.
    static int started = 0;
    log_ = (root_ / ("serve_" + std::to_string(++started) + ".log")).string();
    fs::remove(log_);
    std::vector<std::string> args = {"serve",  model(), scene, "--mu", "1.0",
                                     "--port", "0",     "-j",  "1"};
    args.insert(args.end(), extra.begin(), extra.end());
    pid_ = nsf::testing::spawn_cli(args, log_, in_child);
    for (int i = 0; i < 600; ++i) {
      const std::string text = nsf::testing::read_text(log_);
      const size_t at = text.find("ws://127.0.0.1:");
      if (at != std::string::npos) return std::stoi(text.substr(at + 15));
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return 0;
  }
  void TearDown() override {
    if (pid_ > 0) {
      ::kill(pid_, SIGTERM);
      nsf::testing::wait_child(pid_);
    }
  }

  static inline fs::path root_;
  pid_t pid_ = -1;
  std::string log_;
};

// The next data message (a frame or the model), skipping pings.
inline std::optional<std::string> next_message(WsClient& c) {
  for (;;) {
    const auto f = c.next_frame(20.0);
    if (!f || f->opcode == nsf::net::kClose) return std::nullopt;
    if (f->opcode == nsf::net::kBinary) return f->payload;
  }
}
// The next frame, skipping basis messages (the modes the model message left out).
inline std::optional<StreamFrame> next_frame(WsClient& c) {
  for (;;) {
    const auto m = next_message(c);
    if (!m) return std::nullopt;
    if (m->compare(0, 4, "NSFB") != 0) return decode_frame(*m);
  }
}

}  // namespace nsf::testing::serve
