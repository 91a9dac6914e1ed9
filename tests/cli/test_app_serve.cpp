// `nsf serve` end to end (docs/SERVE.md): a tiny basis model of rom_tiny served on an ephemeral
// port; two clients reconstruct the runtime's positions from the streamed coefficients, one moves
// the floor and both see it move, a malformed client is dropped while the others keep receiving,
// and GET / answers the page. Plus the protocol's parts: the messages' layouts and the commands.
#include <gtest/gtest.h>
#include <signal.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <thread>

#include "app/serve_protocol.h"
#include "cli_child.h"
#include "cli_runner.h"
#include "core/error.h"
#include "data/sweep.h"
#include "nn/basis_decoders.h"
#include "nn/neural_fields.h"
#include "nn/torch_settings.h"
#include "nn/train/trainer.h"
#include "rom/setup/rom_setup.h"
#include "rom/step/latent_stepper.h"
#include "serve_fixture.h"
#include "ws_client.h"

namespace fs = std::filesystem;
using nsf::app::decode_frame;
using nsf::app::decode_model;
using nsf::app::StreamFrame;
using nsf::app::StreamModel;
using nsf::testing::WsClient;
using nsf::testing::serve::kScene;
using nsf::testing::serve::next_frame;
using nsf::testing::serve::next_message;
using nsf::testing::serve::ServeEndToEnd;

namespace {

TEST(ServeProtocol, CommandsAreCheckedStrictly) {
  using nsf::app::parse_command;
  const auto c = parse_command(R"({"type":"move","collider":1,"position":[0.1,0.2,0.3]})", 2);
  EXPECT_EQ(c.kind, nsf::app::ServeCommand::move);
  EXPECT_EQ(c.collider, 1u);
  EXPECT_DOUBLE_EQ(c.position[2], 0.3);
  EXPECT_EQ(parse_command(R"({"type":"reset"})", 0).kind, nsf::app::ServeCommand::reset);
  for (const char* bad :
       {"", "nope", "[]", "{}", R"({"type":"fly"})",
        R"({"type":"move","collider":2,"position":[0,0,0]})",
        R"({"type":"move","collider":-1,"position":[0,0,0]})",
        R"({"type":"move","collider":0.5,"position":[0,0,0]})",
        R"({"type":"move","collider":0,"position":[0,0]})",
        R"({"type":"move","collider":0,"position":[0,0,"a"]})",
        R"({"type":"move","collider":0,"position":[0,0,1e999]})",
        R"({"type":"move","collider":0,"position":[0,0,0],"speed":1})",
        R"({"type":"move","collider":0,"position":[0,0,0],"rotation":[2,0,0,0,1,0,0,0,1]})",
        R"({"type":"reset","x":1})", "{\"type\":\"move\xff\"}"})
    EXPECT_THROW(parse_command(bad, 2), nsf::Error) << bad;
}

// A deformation basis of K modes over two particles (P × 3 × K modes, row-major).
nsf::BasisDecoders two_particle_basis(int K, std::vector<float> mean, std::vector<float> modes) {
  nsf::BasisDecoders b;
  b.rest = {nsf::Vec3(0.1, 0.2, 0.3), nsf::Vec3(0.4, 0.5, 0.6)};
  b.u.dim = 3;
  b.u.K = K;
  b.u.points = 2;
  b.u.mean = std::move(mean);
  b.u.modes = std::move(modes);
  return b;
}

// The model message with the leading modes, then basis messages with the others: a client that
// adds them in order holds every mode, bit for bit, and one that skips one is refused.
TEST(ServeProtocol, ModelAndBasisMessagesAssembleTheWholeBasis) {
  using nsf::app::add_basis;
  using nsf::app::basis_message;
  using nsf::app::model_message;
  using nsf::app::reconstruct;
  std::vector<float> modes;
  for (int i = 0; i < 2 * 3 * 5; ++i) modes.push_back(0.5f * float(i) - 3.25f);
  const nsf::BasisDecoders b = two_particle_basis(5, {1, 2, 3, 4, 5, 6}, modes);
  const std::string model = model_message(b, {{"scene", "two"}}, 2);
  std::optional<StreamModel> m = decode_model(model);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->K, 5);
  EXPECT_EQ(m->received, 2);
  EXPECT_EQ(m->header.at("scene"), "two");
  // The header, then rest, mean and 2 of the 5 modes.
  const size_t data_at = m->header.at("arrays")[0].at("offset").get<size_t>();
  EXPECT_EQ(model.size(), data_at + 4 * 2 * (3 + 3 + 3 * 2));
  const std::string first = basis_message(b, 2, 2), last = basis_message(b, 4, 1);
  EXPECT_EQ(first.size(), nsf::app::kBasisHeaderBytes + 4 * 2 * 3 * 2);
  EXPECT_FALSE(add_basis(*m, last)) << "modes 4.. before modes 2..";
  EXPECT_FALSE(add_basis(*m, first.substr(0, first.size() - 4)));
  const std::vector<float> c = {1, -1, 0.5f, 2, -0.25f};
  const std::vector<float> whole = reconstruct(*decode_model(model_message(b, {}, 5)), c);
  EXPECT_NE(reconstruct(*m, c), whole);
  ASSERT_TRUE(add_basis(*m, first));
  ASSERT_TRUE(add_basis(*m, last));
  EXPECT_EQ(m->received, 5);
  EXPECT_EQ(m->modes, b.u.modes);
  EXPECT_FALSE(add_basis(*m, last)) << "a mode twice";
  EXPECT_EQ(reconstruct(*m, c), whole);
  EXPECT_EQ(nsf::app::modes_per_message(2, 1), 1);
  EXPECT_EQ(nsf::app::modes_per_message(2, 48), 2);

  // A header claiming 70,000 modes (the JSON's padding keeps the layout) is refused, not held.
  const std::string all = model_message(b, {}, 5);
  uint32_t H = 0;
  std::memcpy(&H, all.data() + 4, 4);
  std::string header = all.substr(8, H);
  const size_t at = header.find("\"modes\":5,");
  ASSERT_NE(at, std::string::npos) << header;
  header.replace(at, 10, "\"modes\":70000,");
  header.erase(header.size() - 4);
  ASSERT_TRUE(decode_model(all));
  EXPECT_FALSE(decode_model(all.substr(0, 8) + header + all.substr(8 + H)));
}

TEST(ServeProtocol, FrameLayoutRoundTrips) {
  Eigen::VectorXd z(3);
  z << 0.25, -1.5, 3;
  Eigen::VectorXf c(4);
  c << 1, 2, 3, 4;
  std::vector<nsf::app::StreamPose> poses(2);
  poses[1][5] = 7;
  const std::string m = nsf::app::frame_message(12, 0.5, 1e9, z, c, poses, 0.25f);
  EXPECT_EQ(m.size(), 40u + 8 * 3 + 4 * 4 + 48 * 2);
  const auto f = decode_frame(m);
  ASSERT_TRUE(f);
  EXPECT_EQ(f->frame, 12u);
  EXPECT_EQ(f->time, 0.5);
  EXPECT_EQ(f->indicator, 0.25f);
  EXPECT_EQ(f->z, (std::vector<double>{0.25, -1.5, 3}));
  EXPECT_EQ(f->c, (std::vector<float>{1, 2, 3, 4}));
  EXPECT_EQ(f->poses[1][5], 7.f);
  EXPECT_TRUE(f->rigid.empty());
  EXPECT_FALSE(decode_frame(m.substr(0, m.size() - 1)));
  // A rigid frame's map follows the colliders'; a client knows how many from the length.
  std::vector<nsf::app::StreamPose> rigid(1);
  rigid[0][11] = -2;
  const std::string framed = nsf::app::frame_message(12, 0.5, 1e9, z, c, poses, 0.25f, rigid);
  EXPECT_EQ(framed.size(), m.size() + 48);
  const auto g = decode_frame(framed);
  ASSERT_TRUE(g);
  EXPECT_EQ(g->poses, poses);
  EXPECT_EQ(g->rigid, rigid);
  EXPECT_FALSE(decode_frame(framed + "1234"));
}

// A run with rigid frames (rom.rigid_frames) sends each particle's frame once, in the model
// message, and each frame's map x = R y + o in every frame message: the client moves the
// particles of a frame by it and leaves the others as the basis puts them.
TEST(ServeProtocol, RigidFramesMoveTheirParticlesAlone) {
  using nsf::app::model_message;
  // c moves particle 0 along x.
  const nsf::BasisDecoders b = two_particle_basis(1, {0, 0, 0, 0, 0, 0}, {1, 0, 0, 0, 0, 0});
  EXPECT_EQ(decode_model(model_message(b, {}, 1))->header.at("rigid_frames"), 0);
  const std::optional<StreamModel> m = decode_model(model_message(b, {}, 1, {-1, 0}));
  ASSERT_TRUE(m);
  EXPECT_EQ(m->header.at("rigid_frames"), 1);
  EXPECT_EQ(m->frame, (std::vector<float>{-1, 0}));
  // Turned a quarter about z and shifted up: particle 1 at (−0.5, 0.4, 0.6) + (0, 1, 0).
  const nsf::Mat3 R = Eigen::AngleAxisd(M_PI / 2, nsf::Vec3::UnitZ()).toRotationMatrix();
  const std::vector<nsf::app::StreamPose> rigid = {nsf::app::stream_pose(nsf::Vec3(0, 1, 0), R)};
  const std::vector<float> x = nsf::app::reconstruct(*m, {0.5f}, rigid);
  EXPECT_NEAR(x[0], 0.6f, 1e-7);
  EXPECT_NEAR(x[1], 0.2f, 1e-7);
  EXPECT_NEAR(x[3], -0.5f, 1e-6);
  EXPECT_NEAR(x[4], 1.4f, 1e-6);
  EXPECT_NEAR(x[5], 0.6f, 1e-7);
  EXPECT_EQ(nsf::app::reconstruct(*m, {0.5f})[3], 0.4f) << "no map streamed yet: as the basis";
  // A particle claiming a frame the header does not count is refused.
  std::string bad = model_message(b, {}, 1, {-1, 0});
  const size_t at = bad.find("\"rigid_frames\":1");
  ASSERT_NE(at, std::string::npos);
  bad.replace(at, 16, "\"rigid_frames\":0");
  EXPECT_FALSE(decode_model(bad));
}

TEST_F(ServeEndToEnd, ClientsReconstructTheRuntimesPositionsAndMoveAColliderTogether) {
  const int port = start({"--fps", "30", "--frames", "2000"});
  ASSERT_GT(port, 0) << nsf::testing::read_text(log_);
  WsClient a, b;
  ASSERT_TRUE(a.connect(port));
  ASSERT_TRUE(b.connect(port));

  // Each client gets the model once, first.
  const auto ma = next_message(a), mb = next_message(b);
  ASSERT_TRUE(ma && mb);
  EXPECT_EQ(*ma, *mb);
  const std::optional<StreamModel> m = decode_model(*ma);
  ASSERT_TRUE(m);
  const nsf::NeuralFields fields = nsf::NeuralFields::load(model());
  const nsf::BasisDecoders& bases = *fields.bases();
  ASSERT_EQ(m->header.at("particles").get<size_t>(), bases.rest.size());
  EXPECT_EQ(m->K, bases.u.K);
  EXPECT_EQ(m->header.at("colliders").size(), 1u);

  // A frame: ẑ and c; the positions a client reconstructs from c are g(ẑ), as the runtime's.
  std::optional<StreamFrame> f = next_frame(a);
  ASSERT_TRUE(f);
  f = next_frame(a);  // the first may be the frame held for newcomers: take a fresh one too
  ASSERT_TRUE(f);
  EXPECT_EQ(f->z.size(), 3u);
  ASSERT_EQ(f->c.size(), size_t(m->K));
  EXPECT_EQ(f->poses.size(), 1u);
  const std::vector<float> x = nsf::app::reconstruct(*m, f->c);
  // The runtime stepped in this process to the same frame, on one thread like the server.
  nsf::set_nn_threads(1);
  nsf::RomSetup s = nsf::rom_setup(fields, kScene, 1.0, {}, 0);
  nsf::LatentStepper stepper(const_cast<nsf::NeuralFields&>(fields), std::move(s.scene), s.mu,
                             s.options);
  for (uint32_t k = 0; k < f->frame; ++k) stepper.advance_frame();
  nsf::set_nn_threads(2);
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(stepper.latent()[i], f->z[size_t(i)], 1e-9 * (1 + std::abs(f->z[size_t(i)])));
  std::vector<nsf::Vec3> xr;
  stepper.particle_state(xr, nullptr);
  ASSERT_EQ(x.size(), 3 * xr.size());
  double worst = 0;
  for (size_t p = 0; p < xr.size(); ++p)
    for (int k = 0; k < 3; ++k)
      worst = std::max(worst, std::abs(double(x[3 * p + size_t(k)]) - double(float(xr[p][k]))));
  EXPECT_LT(worst, 4e-7) << "frame " << f->frame << ": the streamed coefficients reconstruct "
                         << "positions other than the runtime's (float32 spacing near 1 m: 6e-8)";

  // b moves the floor up; both clients see it in later frames.
  const float y0 = f->poses[0][1];
  ASSERT_TRUE(b.send_text(R"({"type":"move","collider":0,"position":[0,0.2,0]})"));
  auto sees_floor_at = [](WsClient& c, float y) {
    for (int k = 0; k < 60; ++k) {
      const auto g = next_frame(c);
      if (!g) return false;
      if (std::abs(g->poses[0][1] - y) < 1e-5) return true;
    }
    return false;
  };
  EXPECT_NEAR(y0, 0.12f, 1e-6);
  EXPECT_TRUE(sees_floor_at(a, 0.2f));
  EXPECT_TRUE(sees_floor_at(b, 0.2f));

  // A malformed client is dropped with one log line; a and b go on without a gap.
  WsClient bad;
  ASSERT_TRUE(bad.connect(port));
  ASSERT_TRUE(bad.send_text("{not json"));
  EXPECT_TRUE(bad.closed_by_server(10.0));
  for (WsClient* c : {&a, &b}) {
    auto g = next_frame(*c);
    ASSERT_TRUE(g);
    for (int k = 0; k < 10; ++k) {
      const auto h = next_frame(*c);
      ASSERT_TRUE(h);
      EXPECT_EQ(h->frame, g->frame + 1) << "a frame was lost";
      g = h;
    }
  }
  // A client flooding commands is dropped too.
  WsClient flood;
  ASSERT_TRUE(flood.connect(port));
  std::string burst;
  const uint8_t mask[4] = {1, 2, 3, 4};
  for (int k = 0; k < 200; ++k)
    burst += nsf::net::encode_frame(nsf::net::kText,
                                    R"({"type":"move","collider":0,"position":[0,0.2,0]})", mask);
  ASSERT_TRUE(flood.send_raw(burst));
  EXPECT_TRUE(flood.closed_by_server(10.0));
  // A command that would forge a log line of its own, in red, is dropped with an escaped one.
  WsClient forger;
  ASSERT_TRUE(forger.connect(port));
  ASSERT_TRUE(forger.send_text(R"({"type":"\n\u001b[31mnsf serve: FAKE"})"));
  EXPECT_TRUE(forger.closed_by_server(10.0));
  ASSERT_TRUE(next_frame(a));
  const std::string log = nsf::testing::read_text(log_);
  EXPECT_EQ(log.find("\nnsf serve: FAKE"), std::string::npos) << log;
  EXPECT_EQ(log.find('\x1b'), std::string::npos) << log;
  EXPECT_NE(log.find("an unknown command type '\\x0a\\x1b[31mnsf serve: FAKE'"), std::string::npos)
      << log;
  size_t drops = 0;
  for (size_t at = log.find("dropped client"); at != std::string::npos;
       at = log.find("dropped client", at + 1))
    ++drops;
  EXPECT_EQ(drops, 3u) << log;
  EXPECT_NE(log.find("over 64 commands in one frame"), std::string::npos) << log;
  EXPECT_NE(log.find("a command that is not JSON"), std::string::npos) << log;

  // The page, from the same port.
  WsClient browser;
  const std::string page = browser.http_get(port, "/");
  EXPECT_EQ(page.rfind("HTTP/1.1 200 OK", 0), 0u);
  EXPECT_NE(page.find("new WebSocket("), std::string::npos);
  EXPECT_NE(page.find("NSFF"), std::string::npos);
}

// --basis-message 1: the model message holds rest, mean and one mode, the newcomer's first
// frame follows it, and the other modes arrive one message each between frames; assembled, they
// are the model's basis bit for bit.
TEST_F(ServeEndToEnd, TheBasisFollowsTheFirstFrameAMessageAtATime) {
  const int port = start({"--fps", "30", "--frames", "2000", "--basis-message", "1"});
  ASSERT_GT(port, 0) << nsf::testing::read_text(log_);
  const nsf::NeuralFields fields = nsf::NeuralFields::load(model());
  const nsf::BasisDecoders& bases = *fields.bases();
  ASSERT_GT(bases.u.K, 2);
  WsClient a;
  ASSERT_TRUE(a.connect(port));
  const auto first = next_message(a);
  ASSERT_TRUE(first);
  std::optional<StreamModel> m = decode_model(*first);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->received, 1);
  EXPECT_EQ(m->K, bases.u.K);
  const size_t P = bases.rest.size();
  EXPECT_LT(first->size(), 4 * P * (6 + 3 * size_t(bases.u.K)));
  const auto second = next_message(a);
  ASSERT_TRUE(second && decode_frame(*second)) << "the first frame waits for the whole basis";
  int frames = 0, parts = 0;
  while (m->received < m->K && frames < 200) {
    const auto msg = next_message(a);
    ASSERT_TRUE(msg);
    if (decode_frame(*msg)) {
      ++frames;
      continue;
    }
    ASSERT_TRUE(nsf::app::add_basis(*m, *msg)) << "not the next modes";
    ++parts;
  }
  EXPECT_EQ(m->received, m->K);
  EXPECT_EQ(parts, bases.u.K - 1);
  EXPECT_EQ(m->modes, bases.u.modes);
}

// Another site's page open in the browser may not drive the server (cross-site WebSocket
// hijacking), nor may a page that reached it under another name (DNS rebinding): 403 and a log
// line. The server's own page and programs (no Origin) connect; --allow-origin adds a site.
// At the scene's last frame (12 frames of 15 ms) the stream starts it again, or holds it, instead
// of stepping on into a pose no training run reached (--at-end).
TEST_F(ServeEndToEnd, AtTheScenesEndTheStreamLoopsOrHolds) {
  for (const std::string mode : {"loop", "hold", "continue"}) {
    SCOPED_TRACE(mode);
    const int port = start({"--fps", "200", "--frames", "100000", "--at-end", mode});
    ASSERT_GT(port, 0) << nsf::testing::read_text(log_);
    WsClient c;
    ASSERT_TRUE(c.connect(port));
    const auto m = next_message(c);
    ASSERT_TRUE(m && decode_model(*m));
    EXPECT_EQ(decode_model(*m)->header.value("at_end", ""), mode);
    std::vector<double> times;
    for (int k = 0; k < 30; ++k) {
      const auto f = next_frame(c);
      ASSERT_TRUE(f);
      times.push_back(f->time);
    }
    const double end = 12 * 0.015, latest = *std::max_element(times.begin(), times.end());
    bool restarted = false, held = false;
    for (size_t k = 1; k < times.size(); ++k) {
      restarted |= times[k] < times[k - 1];
      held |= times[k] == times[k - 1] && times[k] >= end - 1e-9;
    }
    if (mode == "continue") {
      EXPECT_GT(latest, end + 0.01);
    } else {
      EXPECT_LE(latest, end + 1e-9);
      EXPECT_EQ(restarted, mode == "loop");
      EXPECT_EQ(held, mode == "hold");
    }
    ::kill(pid_, SIGTERM);
    nsf::testing::wait_child(pid_);
    pid_ = -1;
  }
}

TEST_F(ServeEndToEnd, RefusesOtherSitesPagesUnlessAllowed) {
  const int port = start({"--fps", "30", "--frames", "100000", "--allow-origin",
                          "http://example.org", "--allow-origin", "http://example.net:8000"});
  ASSERT_GT(port, 0) << nsf::testing::read_text(log_);
  const std::string own = "http://127.0.0.1:" + std::to_string(port);
  const auto opens = [&](const std::string& origin, const std::string& host = "") {
    WsClient c;
    c.origin = origin;
    c.host = host;
    const bool ok = c.connect(port);
    EXPECT_EQ(c.response_head().rfind(ok ? "HTTP/1.1 101" : "HTTP/1.1 403", 0), 0u)
        << c.response_head();
    return ok;
  };
  EXPECT_TRUE(opens(""));
  EXPECT_TRUE(opens(own));
  EXPECT_TRUE(opens("http://example.org"));
  EXPECT_TRUE(opens("http://example.net:8000"));
  EXPECT_FALSE(opens("http://evil.example.com"));
  EXPECT_FALSE(opens("http://example.net"));
  EXPECT_FALSE(opens("", "evil.example.com:" + std::to_string(port)));
  std::string log;
  for (int k = 0; k < 50; ++k) {  // the log is written as the server goes
    log = nsf::testing::read_text(log_);
    if (log.find("'http://example.net'") != std::string::npos) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_NE(log.find("refused client"), std::string::npos) << log;
  EXPECT_NE(log.find("Origin 'http://evil.example.com' is not this server's page"),
            std::string::npos)
      << log;
}

// A run whose rom settings move the bar in a rigid frame (rom.rigid_frames) streams the frame's map
// beside the coefficients; the client's positions are the runtime's, framed (the frame carries
// the bar's fall: centimetres by the frame taken).
TEST_F(ServeEndToEnd, AClientReconstructsARunInRigidFrames) {
  const std::string frames = "rom.rigid_frames=[0]";
  const int port = start({"--fps", "30", "--frames", "2000", "--set", frames});
  ASSERT_GT(port, 0) << nsf::testing::read_text(log_);
  WsClient a;
  ASSERT_TRUE(a.connect(port));
  const auto ma = next_message(a);
  ASSERT_TRUE(ma);
  const std::optional<StreamModel> m = decode_model(*ma);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->header.at("rigid_frames"), 1);
  ASSERT_EQ(m->frame.size(), m->rest.size() / 3);
  EXPECT_EQ(*std::min_element(m->frame.begin(), m->frame.end()), 0.f) << "one object, framed";
  std::optional<StreamFrame> f = next_frame(a);
  for (int k = 0; k < 4 && f; ++k) f = next_frame(a);
  ASSERT_TRUE(f);
  ASSERT_EQ(f->rigid.size(), 1u);
  const std::vector<float> x = nsf::app::reconstruct(*m, f->c, f->rigid);

  const nsf::NeuralFields fields = nsf::NeuralFields::load(model());
  nsf::set_nn_threads(1);
  nsf::RomSetup s = nsf::rom_setup(fields, kScene, 1.0, {frames}, 0);
  nsf::LatentStepper stepper(const_cast<nsf::NeuralFields&>(fields), std::move(s.scene), s.mu,
                             s.options);
  // To the frame's time (the stream loops at the scene's end, its frame numbers do not).
  const long n = std::lround(f->time / m->header.at("frame_time").get<double>());
  for (long k = 0; k < n; ++k) stepper.advance_frame();
  nsf::set_nn_threads(2);
  std::vector<nsf::Vec3> xr;
  stepper.particle_state(xr, nullptr);
  ASSERT_EQ(x.size(), 3 * xr.size());
  double worst = 0, by_frame = 0;
  const std::vector<float> plain = nsf::app::reconstruct(*m, f->c);
  for (size_t p = 0; p < xr.size(); ++p)
    for (int k = 0; k < 3; ++k) {
      worst = std::max(worst, std::abs(double(x[3 * p + size_t(k)]) - xr[p][k]));
      by_frame = std::max(by_frame, std::abs(double(plain[3 * p + size_t(k)]) - xr[p][k]));
    }
  // float32 arithmetic of a rotation about the body's centre: a few spacings of 6e-8 at 1 m.
  EXPECT_LT(worst, 1e-6) << "frame " << f->frame << ": the client's framed positions are not the "
                         << "runtime's";
  EXPECT_GT(by_frame, 1e-3) << "the frame did not move the bar: the test shows nothing";
}

TEST_F(ServeEndToEnd, RefusesABadAddressAndAnMlpModelAndStopsAfterItsFrames) {
  const auto bad = nsf::testing::run_cli("serve '" + model() + "' '" + kScene +
                                         "' --mu 1.0 --bind localhost --port 0");
  EXPECT_EQ(bad.exit_code, 1) << bad.output;
  EXPECT_NE(bad.output.find("not an IPv4 address"), std::string::npos) << bad.output;
  // A model with MLP decoders has no coefficients to stream.
  nsf::TrainOptions o;
  o.config.net.decoder = nsf::DecoderFamily::mlp;
  o.config.net.latent_dim = 2;
  o.config.net.depth = 2;
  o.config.net.width_g = o.config.net.width_h = o.config.net.width_l = 8;
  o.config.net.encoder_hidden = 4;
  o.config.steps = {5, 2, 2};
  o.config.quiet = true;
  const std::string mlp = (root_ / "tiny_mlp.nsf").string();
  nsf::train_model((root_ / "data").string(), mlp, o);
  const auto refused =
      nsf::testing::run_cli("serve '" + mlp + "' '" + kScene + "' --mu 1.0 --port 0");
  EXPECT_EQ(refused.exit_code, 1) << refused.output;
  EXPECT_NE(refused.output.find("MLP decoders"), std::string::npos) << refused.output;
  const auto run = nsf::testing::run_cli("serve '" + model() + "' '" + kScene +
                                         "' --mu 1.0 --port 0 --fps 0 --frames 5 -j 1");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("nsf serve: 5 frames"), std::string::npos) << run.output;
}

}  // namespace

namespace {

// Runs `command` and returns its standard output.
std::string capture(const std::string& command) {
  std::string out;
  if (FILE* p = ::popen(command.c_str(), "r")) {
    char buf[65536];
    size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
    ::pclose(p);
  }
  return out;
}

// The text of <pre id="ID"> in a dumped DOM ("" when absent or empty).
std::string pre_text(const std::string& dom, const std::string& id) {
  const std::string open = "<pre id=\"" + id + "\">";
  const size_t a = dom.find(open);
  if (a == std::string::npos) return "";
  const size_t b = dom.find("</pre>", a);
  return dom.substr(a + open.size(), b - a - open.size());
}

}  // namespace

// The page in headless Chromium (Debian's `chromium`): it connects, assembles the basis from
// its parts, reconstructs a frame in JavaScript, moves it by the streamed rigid frame, and its
// positions are the runtime's at that frame's latent and frame to float32 precision; it also draws
// them (WebGL, software) into a PNG it leaves in the DOM.
TEST_F(ServeEndToEnd, PageInHeadlessChromiumReconstructsTheRuntimesPositions) {
  if (std::system("command -v chromium >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "no chromium on this machine (scripts/install-deps.sh installs it)";
  // One mode per message: the page assembles the basis from its parts before it writes positions.
  // The bar in a rigid frame (rom.rigid_frames): the page moves it by the streamed map too.
  const int port = start({"--fps", "20", "--frames", "100000", "--basis-message", "1", "--set",
                          "rom.rigid_frames=[0]"});
  ASSERT_GT(port, 0) << nsf::testing::read_text(log_);
  // A profile of its own (a second chromium on a shared profile hands its page to the first and
  // exits), its messages kept for a failure.
  const std::string profile = (root_ / "chromium_profile").string(),
                    err = (root_ / "chromium.err").string();
  std::string dump, dom;
  for (int attempt = 0; attempt < 3 && dump.empty(); ++attempt) {
    dom = capture(
        "timeout 120 chromium --headless --no-sandbox --enable-unsafe-swiftshader "
        "--no-first-run --user-data-dir='" +
        profile +
        "' --window-size=320,240 "
        "--virtual-time-budget=10000 --dump-dom 'http://127.0.0.1:" +
        std::to_string(port) + "/?dump=3' 2>'" + err + "'");
    dump = pre_text(dom, "dump");
  }
  ASSERT_FALSE(dump.empty()) << "the page wrote no positions; its DOM:\n"
                             << dom.substr(0, 2000) << "\nchromium said:\n"
                             << nsf::testing::read_text(err).substr(0, 4000);
  const nlohmann::json j = nlohmann::json::parse(dump);
  const uint32_t frame = j.at("frame");
  EXPECT_GE(frame, 3u);
  const std::vector<double> x = j.at("positions");

  // The runtime's positions at the page's latent and frame: R g(X, ẑ) + o, as
  // nsf::Runtime::positions gives them (that the streamed ẑ and map are the stepper's own is
  // checked above).
  const nsf::NeuralFields fields = nsf::NeuralFields::load(model());
  const std::vector<double> z = j.at("z");
  ASSERT_EQ(z.size(), 3u);
  const std::vector<std::vector<double>> rigid = j.at("rigid");
  ASSERT_EQ(rigid.size(), 1u);
  ASSERT_EQ(rigid[0].size(), 12u);
  nsf::Mat3 R;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) R(a, b) = rigid[0][size_t(3 + 3 * a + b)];
  const nsf::Vec3 o(rigid[0][0], rigid[0][1], rigid[0][2]);
  std::vector<nsf::Vec3> xr;
  fields.deform(fields.prepare(fields.bases()->rest),
                Eigen::Map<const Eigen::VectorXd>(z.data(), 3), xr);
  ASSERT_EQ(x.size(), 3 * xr.size());
  double worst = 0;
  for (size_t p = 0; p < xr.size(); ++p) {
    const nsf::Vec3 y = R * xr[p] + o;
    for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(x[3 * p + size_t(k)] - y[k]));
  }
  // float32 arithmetic, a rotation included: a few spacings of 6e-8 at 1 m.
  EXPECT_LT(worst, 1e-6) << "frame " << frame << ": the page's positions are not the runtime's";
  EXPECT_EQ(pre_text(dom, "snapshot").rfind("data:image/png;base64,", 0), 0u)
      << "the page drew nothing";
}
