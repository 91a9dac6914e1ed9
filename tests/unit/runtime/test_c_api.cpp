// The C API (include/nsf/nsf.h) as a host sees it: this executable links libnsf_runtime.so and
// nothing else of nsf. A tiny model of scenes/examples/rom_tiny.json is trained once by the `nsf`
// tool (SetUpTestSuite); the tests run it through the C calls, next to nsf::Runtime, and drive
// every error path: NULL handles and pointers, short buffers, missing files, bad overrides and
// options, refused poses, a step past the indicator with recover off. No call may throw.
#include <gtest/gtest.h>
#include <nsf/nsf.h>
#include <nsf/runtime.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "c_api_options.h"
#include "cli_runner.h"

extern "C" int nsf_test_c99_run(const char* model, const char* scene, char* message, size_t size);

namespace {

namespace fs = std::filesystem;

std::string quoted_path(const std::string& p) {
  return "'" + p + "'";
}

const std::string kScene =
    (fs::path(NSF_SOURCE_DIR) / "scenes" / "examples" / "rom_tiny.json").string();

std::string last_error() {
  return nsf_last_error();
}

class CApi : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = nsf::testing::fresh_dir("c_api");
    const std::string data = (root_ / "data").string();
    std::string out;
    ASSERT_EQ(nsf::testing::run_cli("sweep " + quoted_path(kScene) + " --out " + quoted_path(data) +
                                        " --jobs 2 -j 1 -q",
                                    out),
              0)
        << out;
    ASSERT_EQ(
        nsf::testing::run_cli("train " + quoted_path(data) + " --out " + quoted_path(model()) +
                                  " -r 2 --depth 2 --widths 32,16,16 --encoder-hidden 8"
                                  " --steps 100,50,50 --refine-latents 0 -j 2 -q"
                                  " --frames-per-batch 2 --particles-per-frame 64",
                              out),
        0)
        << out;
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }
  static std::string model() { return (root_ / "tiny.nsf").string(); }

  void SetUp() override {
    if (!fs::exists(model())) GTEST_SKIP() << "no model: the suite's setup failed";
  }
  void TearDown() override { nsf_runtime_destroy(rom_); }

  static nsf_runtime_options options() { return nsf::testing::tiny_c_api_options(); }
  // A runtime of the tiny model at mu 1 in rom_.
  void create(const nsf_runtime_options& o = options()) {
    ASSERT_EQ(nsf_runtime_create(model().c_str(), kScene.c_str(), &o, &rom_), NSF_OK)
        << last_error();
    ASSERT_NE(rom_, nullptr);
  }
  size_t particles() {
    size_t n = 0;
    EXPECT_EQ(nsf_runtime_particle_count(rom_, &n), NSF_OK);
    return n;
  }

  static inline fs::path root_;
  nsf_runtime* rom_ = nullptr;
};

// The largest difference of two float arrays.
float max_diff(const std::vector<float>& a, const std::vector<float>& b) {
  EXPECT_EQ(a.size(), b.size());
  float worst = 0;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i)
    worst = std::max(worst, std::abs(a[i] - b[i]));
  return worst;
}

bool all_finite(const std::vector<float>& a) {
  for (float v : a)
    if (!std::isfinite(v)) return false;
  return true;
}

TEST_F(CApi, Version) {
  int major = -1, minor = -1, patch = -1;
  ASSERT_EQ(nsf_version_numbers(&major, &minor, &patch), NSF_OK);
  EXPECT_EQ(std::string(nsf_version()),
            std::to_string(major) + "." + std::to_string(minor) + "." + std::to_string(patch));
  EXPECT_EQ(std::string(nsf::version()), std::string(nsf_version()));  // the C++ API's
  // The copy of the library the loader took: built for this CPU's level where the build made one.
  const std::string arch = nsf_build_arch();
  EXPECT_EQ(arch, std::string(nsf::build_arch()));
#if defined(NSF_HWCAPS_COPY) && defined(__x86_64__)
  EXPECT_EQ(arch, __builtin_cpu_supports("x86-64-v3") ? "x86-64-v3" : "x86-64-v2");
#else
  EXPECT_FALSE(arch.empty());
#endif
  EXPECT_EQ(std::string(nsf_status_name(NSF_ERROR_BUFFER_TOO_SMALL)), "NSF_ERROR_BUFFER_TOO_SMALL");
  EXPECT_EQ(std::string(nsf_status_name(static_cast<nsf_status>(1234))), "NSF_UNKNOWN_STATUS");
}

// A good run: the C calls give what nsf::Runtime gives for the same model, scene and options,
// frame after frame, and the run's numbers are the scene's.
TEST_F(CApi, GoodRunMatchesTheCppRuntime) {
  create();
  nsf::RuntimeOptions o;
  o.mu = 1.0;
  o.threads = 2;
  nsf::Runtime cpp(model(), kScene, o);

  const size_t P = particles();
  EXPECT_EQ(P, cpp.particle_count());
  EXPECT_EQ(P, 864u);
  int frames = 0, steps = 0;
  double frame_time = 0, t = -1;
  ASSERT_EQ(nsf_runtime_frame_count(rom_, &frames), NSF_OK);
  ASSERT_EQ(nsf_runtime_steps_per_frame(rom_, &steps), NSF_OK);
  ASSERT_EQ(nsf_runtime_frame_time(rom_, &frame_time), NSF_OK);
  ASSERT_EQ(nsf_runtime_time(rom_, &t), NSF_OK);
  EXPECT_EQ(frames, 12);
  EXPECT_EQ(steps, cpp.steps_per_frame());
  EXPECT_NEAR(frame_time, 0.015, 1e-12);
  EXPECT_EQ(t, 0.0);
  size_t dim = 0;
  ASSERT_EQ(nsf_runtime_latent_dim(rom_, &dim), NSF_OK);
  EXPECT_EQ(dim, 2u);  // -r 2
  EXPECT_EQ(dim, cpp.latent_dim());

  std::vector<float> x(3 * P), v(3 * P), tau(9 * P), z(dim);
  ASSERT_EQ(nsf_runtime_positions(rom_, x.data(), x.size()), NSF_OK);
  const std::vector<float> x0 = x;
  for (int frame = 1; frame <= 3; ++frame) {
    ASSERT_EQ(nsf_runtime_advance_frame(rom_), NSF_OK) << last_error();
    cpp.advance_frame();
    ASSERT_EQ(nsf_runtime_positions(rom_, x.data(), x.size()), NSF_OK);
    ASSERT_EQ(nsf_runtime_velocities(rom_, v.data(), v.size()), NSF_OK);
    ASSERT_EQ(nsf_runtime_stress(rom_, tau.data(), tau.size()), NSF_OK);
    ASSERT_EQ(nsf_runtime_latent(rom_, z.data(), z.size()), NSF_OK);
    EXPECT_TRUE(all_finite(x) && all_finite(v) && all_finite(tau) && all_finite(z));
    std::vector<float> want(3 * P), want_tau(9 * P), want_z(dim);
    cpp.positions(want.data(), want.size());
    EXPECT_LE(max_diff(x, want), 1e-6f) << "frame " << frame;
    cpp.velocities(want.data(), want.size());
    EXPECT_LE(max_diff(v, want), 1e-4f) << "frame " << frame;
    cpp.stress(want_tau.data(), want_tau.size());
    EXPECT_LE(max_diff(tau, want_tau), 1e-3f) << "frame " << frame;
    cpp.latent(want_z.data(), want_z.size());
    EXPECT_LE(max_diff(z, want_z), 1e-6f) << "frame " << frame;
    std::vector<float> C(9 * P), want_C(9 * P);
    ASSERT_EQ(nsf_runtime_affine(rom_, C.data(), C.size()), NSF_OK);
    cpp.affine(want_C.data(), want_C.size());
    EXPECT_LE(max_diff(C, want_C), 1e-3f) << "frame " << frame;
    EXPECT_EQ(nsf_runtime_affine(rom_, C.data(), C.size() - 1), NSF_ERROR_BUFFER_TOO_SMALL);
  }
  ASSERT_EQ(nsf_runtime_time(rom_, &t), NSF_OK);
  EXPECT_NEAR(t, 3 * frame_time, 1e-9);
  EXPECT_GT(max_diff(x, x0), 1e-3f) << "three frames moved nothing";
  // τ is a stress of the material, not zeros (E = 2e4 Pa: a thrown bar's τ is Pa to kPa).
  float largest = 0;
  for (float s : tau) largest = std::max(largest, std::abs(s));
  EXPECT_GT(largest, 1e-3f);
  EXPECT_LT(largest, 1e6f);
  // Symmetric, as the Kirchhoff stress of an isotropic material is (within float rounding).
  for (size_t p = 0; p < P; p += 97)
    EXPECT_NEAR(tau[9 * p + 1], tau[9 * p + 3], 1e-2f + 1e-4f * largest);

  nsf_health h;
  ASSERT_EQ(nsf_runtime_health(rom_, &h), NSF_OK);
  const nsf::RuntimeHealth want = cpp.health();
  EXPECT_EQ(h.indicator, want.indicator);
  EXPECT_EQ(h.misfit_cells, want.misfit_cells);
  EXPECT_EQ(h.courant, want.courant);
  EXPECT_EQ(h.grid_margin, want.grid_margin);
  EXPECT_EQ(h.flagged != 0, want.flagged);
  EXPECT_EQ(h.recoveries, want.recoveries);
  size_t length = 99;
  ASSERT_EQ(nsf_runtime_last_recovery(rom_, nullptr, 0, &length), NSF_OK);
  EXPECT_EQ(length, want.last_recovery.size());

  // The collider: the scene's floor, its pose read and given back, and what the host sets held.
  size_t colliders = 0;
  ASSERT_EQ(nsf_runtime_collider_count(rom_, &colliders), NSF_OK);
  ASSERT_EQ(colliders, 1u);
  char type[16];
  ASSERT_EQ(nsf_runtime_collider_type(rom_, 0, type, sizeof type, &length), NSF_OK);
  EXPECT_EQ(std::string(type), "plane");
  EXPECT_EQ(length, 5u);
  nsf_collider_pose pose;
  ASSERT_EQ(nsf_runtime_collider_pose(rom_, 0, &pose), NSF_OK);
  EXPECT_NEAR(pose.position[1], 0.12, 1e-12);
  EXPECT_EQ(pose.rotation[0], 1.0);
  pose.position[1] = 0.13;
  pose.velocity[1] = 0.5;
  ASSERT_EQ(nsf_runtime_set_collider_pose(rom_, 0, &pose), NSF_OK) << last_error();
  nsf_collider_pose back;
  ASSERT_EQ(nsf_runtime_collider_pose(rom_, 0, &back), NSF_OK);
  EXPECT_NEAR(back.position[1], 0.13, 1e-12);
  EXPECT_NEAR(back.velocity[1], 0.5, 1e-12);
  ASSERT_EQ(nsf_runtime_step(rom_), NSF_OK) << last_error();
  EXPECT_EQ(last_error(), "");
  // The floor never moved in the training runs: moving at 0.5 m/s, it left the training box.
  ASSERT_EQ(nsf_runtime_health(rom_, &h), NSF_OK);
  EXPECT_EQ(h.outside_training, 1);
  EXPECT_EQ(h.steps_outside, 1);
  char note[256];
  ASSERT_EQ(nsf_runtime_training_note(rom_, note, sizeof note, &length), NSF_OK);
  EXPECT_NE(std::string(note).find("faster than its training runs"), std::string::npos) << note;
  // The set-up warned of nothing: the scene is one of the model's training family.
  ASSERT_EQ(nsf_runtime_warnings(rom_, nullptr, 0, &length), NSF_OK);
  EXPECT_EQ(length, 0u);
}

// A scene set outside the model's training family (the floor lower than in every training run)
// is named in the set-up's warnings, one line each.
TEST_F(CApi, ASceneOutsideTheTrainingFamilyIsNamedInTheWarnings) {
  nsf_runtime_options o = options();
  const char* lower[] = {"colliders[0].point=[0,0.07,0]"};
  o.overrides = lower;
  o.override_count = 1;
  create(o);
  size_t length = 0;
  ASSERT_EQ(nsf_runtime_warnings(rom_, nullptr, 0, &length), NSF_OK);
  ASSERT_GT(length, 0u);
  std::vector<char> text(length + 1);
  ASSERT_EQ(nsf_runtime_warnings(rom_, text.data(), text.size(), &length), NSF_OK);
  const std::string w(text.data());
  EXPECT_NE(w.find("outside the model's training family (/colliders/0/point/1"), std::string::npos)
      << w;
  EXPECT_EQ(w.back(), '\n');
}

// With the particles' own tracked state as the step's τ (rom.fields.stress = "tracked"), stress
// gives that state: finite, and not the decoder's.
TEST_F(CApi, StressFromTheTrackedState) {
  nsf_runtime_options o = options();
  const char* tracked[] = {R"(rom={"samples":64,"fields":{"stress":"tracked"}})"};
  o.overrides = tracked;
  o.override_count = 1;
  create(o);
  nsf_runtime* decoder = nullptr;
  const nsf_runtime_options plain = options();
  ASSERT_EQ(nsf_runtime_create(model().c_str(), kScene.c_str(), &plain, &decoder), NSF_OK);
  const size_t P = particles();
  std::vector<float> tau(9 * P), want(9 * P);
  ASSERT_EQ(nsf_runtime_advance_frame(rom_), NSF_OK) << last_error();
  ASSERT_EQ(nsf_runtime_advance_frame(decoder), NSF_OK) << last_error();
  ASSERT_EQ(nsf_runtime_stress(rom_, tau.data(), tau.size()), NSF_OK) << last_error();
  ASSERT_EQ(nsf_runtime_stress(decoder, want.data(), want.size()), NSF_OK) << last_error();
  nsf_runtime_destroy(decoder);
  EXPECT_TRUE(all_finite(tau));
  EXPECT_GT(max_diff(tau, want), 1e-3f) << "the tracked τ is the decoder's";
}

// nsf::Runtime::affine (C++ only): C of every particle, 9 floats each, finite, the same on a second
// call; zero with rom.fields.affine = "none"; a short buffer throws and is left untouched.
TEST_F(CApi, CppAffineField) {
  nsf::RuntimeOptions o;
  o.mu = 1.0;
  o.threads = 2;
  nsf::Runtime rt(model(), kScene, o);
  const std::size_t P = rt.particle_count();
  rt.advance_frame();
  std::vector<float> C(9 * P, NAN), again(9 * P, NAN);
  rt.affine(C.data(), C.size());
  rt.affine(again.data(), again.size());
  EXPECT_TRUE(all_finite(C));
  EXPECT_EQ(C, again);
  float largest = 0;
  for (float c : C) largest = std::max(largest, std::abs(c));
  EXPECT_GT(largest, 0.0f) << "the decoder's C is zero everywhere";
  std::vector<float> small(9 * P - 1, 7.0f);
  EXPECT_THROW(rt.affine(small.data(), small.size()), std::runtime_error);
  EXPECT_EQ(small.front(), 7.0f);

  o.overrides = {R"(rom={"samples":64,"fields":{"affine":"none"}})"};
  nsf::Runtime none(model(), kScene, o);
  none.advance_frame();
  none.affine(C.data(), C.size());
  EXPECT_EQ(C, std::vector<float>(9 * P, 0.0f));
}

// A NULL handle or out pointer is NSF_ERROR_NULL_POINTER with a message, for every call.
// The thrown bar as a rigid body: it starts near its throw's velocity (the tiny model's ẑ₋₁ fits
// X − Δt v⁰ on 64 samples to a few percent), its centre is its particles'
// (one material, equal masses), and its centre's velocity is the last step's backward difference
// of that centre, as the particles' is of theirs.
TEST_F(CApi, AnObjectsPoseFollowsItsParticles) {
  create();
  size_t objects = 0;
  ASSERT_EQ(nsf_runtime_object_count(rom_, &objects), NSF_OK);
  ASSERT_EQ(objects, 1u);
  const size_t n = particles();
  std::vector<float> x(3 * n);
  const auto centre = [&] {
    EXPECT_EQ(nsf_runtime_positions(rom_, x.data(), x.size()), NSF_OK);
    double c[3] = {0, 0, 0};
    for (size_t p = 0; p < n; ++p)
      for (int k = 0; k < 3; ++k) c[k] += x[3 * p + size_t(k)] / double(n);
    return std::vector<double>(c, c + 3);
  };
  nsf_object_pose at0, a, b;
  ASSERT_EQ(nsf_runtime_object_pose(rom_, 0, &at0), NSF_OK) << last_error();
  EXPECT_NEAR(at0.velocity[0], 1.0, 0.05);
  EXPECT_NEAR(at0.velocity[1], -1.0, 0.05);
  EXPECT_NEAR(at0.velocity[2], 0.0, 0.05);
  ASSERT_EQ(nsf_runtime_advance_frame(rom_), NSF_OK) << last_error();
  ASSERT_EQ(nsf_runtime_object_pose(rom_, 0, &a), NSF_OK);
  const std::vector<double> ca = centre();
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(a.position[k], ca[size_t(k)], 1e-6);
    EXPECT_EQ(a.rest_position[k], at0.rest_position[k]);
  }
  double dt = 0;
  int per_frame = 0;
  ASSERT_EQ(nsf_runtime_frame_time(rom_, &dt), NSF_OK);
  ASSERT_EQ(nsf_runtime_steps_per_frame(rom_, &per_frame), NSF_OK);
  dt /= per_frame;
  ASSERT_EQ(nsf_runtime_step(rom_), NSF_OK);
  ASSERT_EQ(nsf_runtime_object_pose(rom_, 0, &b), NSF_OK);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(b.velocity[k], (b.position[k] - a.position[k]) / dt, 1e-7 / dt) << k;
  // A rotation, and a misfit of a body that is soft but not torn apart (a few millimetres).
  double det = 0;
  const double* R = b.rotation;
  det = R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) +
        R[2] * (R[3] * R[7] - R[4] * R[6]);
  EXPECT_NEAR(det, 1.0, 1e-12);
  EXPECT_GE(b.misfit, 0.0);
  EXPECT_LT(b.misfit, 0.02);
  EXPECT_EQ(nsf_runtime_object_pose(rom_, 1, &b), NSF_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(last_error().find("object 1 does not exist: the scene has 1"), std::string::npos)
      << last_error();
  // The bar spun about z in a rigid frame (no training run spun it): it starts at that spin and
  // keeps turning the same way, its rotation about z.
  nsf_runtime_destroy(rom_);
  rom_ = nullptr;
  nsf_runtime_options o = options();
  const char* spin[] = {"objects[0].angular_velocity=[0,0,4]", "rom.rigid_frames=[0]"};
  o.overrides = spin;
  o.override_count = 2;
  create(o);
  ASSERT_EQ(nsf_runtime_object_pose(rom_, 0, &at0), NSF_OK);
  EXPECT_NEAR(at0.angular_velocity[2], 4.0, 0.04);
  EXPECT_LT(std::hypot(at0.angular_velocity[0], at0.angular_velocity[1]), 0.04);
  ASSERT_EQ(nsf_runtime_advance_frame(rom_), NSF_OK) << last_error();
  ASSERT_EQ(nsf_runtime_object_pose(rom_, 0, &a), NSF_OK);
  const double turned = std::atan2(a.rotation[3], a.rotation[0]);  // about z, over one frame
  ASSERT_EQ(nsf_runtime_frame_time(rom_, &dt), NSF_OK);
  EXPECT_GT(turned, 0.5 * 4 * dt);
  EXPECT_LT(turned, 1.05 * 4 * dt);
  EXPECT_GT(a.angular_velocity[2], 2.0);
}

TEST_F(CApi, NullHandleAndPointers) {
  float f[9];
  size_t n = 0;
  int i = 0;
  double d = 0;
  nsf_health h;
  nsf_collider_pose pose;
  nsf_object_pose object;
  char text[16];
  const auto null = [](nsf_status s) {
    EXPECT_EQ(s, NSF_ERROR_NULL_POINTER) << nsf_status_name(s);
    EXPECT_NE(last_error().find("NULL"), std::string::npos) << last_error();
  };
  null(nsf_runtime_particle_count(nullptr, &n));
  null(nsf_runtime_frame_count(nullptr, &i));
  null(nsf_runtime_frame_time(nullptr, &d));
  null(nsf_runtime_steps_per_frame(nullptr, &i));
  null(nsf_runtime_time(nullptr, &d));
  null(nsf_runtime_step(nullptr));
  null(nsf_runtime_advance_frame(nullptr));
  null(nsf_runtime_positions(nullptr, f, 9));
  null(nsf_runtime_velocities(nullptr, f, 9));
  null(nsf_runtime_stress(nullptr, f, 9));
  null(nsf_runtime_latent_dim(nullptr, &n));
  null(nsf_runtime_latent(nullptr, f, 9));
  null(nsf_runtime_health(nullptr, &h));
  null(nsf_runtime_last_recovery(nullptr, text, sizeof text, &n));
  null(nsf_runtime_collider_count(nullptr, &n));
  null(nsf_runtime_collider_type(nullptr, 0, text, sizeof text, &n));
  null(nsf_runtime_collider_pose(nullptr, 0, &pose));
  null(nsf_runtime_set_collider_pose(nullptr, 0, &pose));
  null(nsf_runtime_object_count(nullptr, &n));
  null(nsf_runtime_object_pose(nullptr, 0, &object));
  null(nsf_version_numbers(nullptr, &i, &i));
  null(nsf_runtime_options_init(nullptr));
  EXPECT_EQ(last_error(), "nsf_runtime_options_init: options is NULL");
  nsf_runtime_destroy(nullptr);  // ignored, as free(NULL)

  const nsf_runtime_options o = options();
  null(nsf_runtime_create(model().c_str(), kScene.c_str(), &o, nullptr));
  nsf_runtime* rom = reinterpret_cast<nsf_runtime*>(&n);  // set to NULL by a failed create
  null(nsf_runtime_create(nullptr, kScene.c_str(), &o, &rom));
  EXPECT_EQ(rom, nullptr);
  null(nsf_runtime_create(model().c_str(), nullptr, &o, &rom));

  // A live handle with NULL outs.
  create();
  null(nsf_runtime_particle_count(rom_, nullptr));
  null(nsf_runtime_time(rom_, nullptr));
  null(nsf_runtime_positions(rom_, nullptr, 3 * particles()));
  null(nsf_runtime_stress(rom_, nullptr, 9 * particles()));
  null(nsf_runtime_health(rom_, nullptr));
  null(nsf_runtime_last_recovery(rom_, text, sizeof text, nullptr));
  null(nsf_runtime_collider_type(rom_, 0, nullptr, 16, &n));
  null(nsf_runtime_collider_pose(rom_, 0, nullptr));
  null(nsf_runtime_set_collider_pose(rom_, 0, nullptr));
  // NULL overrides with a count, or a NULL override among them.
  nsf_runtime_options bad = options();
  bad.override_count = 1;
  nsf_runtime* other = nullptr;
  null(nsf_runtime_create(model().c_str(), kScene.c_str(), &bad, &other));
  const char* overrides[] = {"simulation.frames=3", nullptr};
  bad.overrides = overrides;
  bad.override_count = 2;
  null(nsf_runtime_create(model().c_str(), kScene.c_str(), &bad, &other));
  EXPECT_NE(last_error().find("overrides[1]"), std::string::npos) << last_error();
  EXPECT_EQ(other, nullptr);
}

// A buffer too small is NSF_ERROR_BUFFER_TOO_SMALL, saying how many are needed, and is left
// untouched; a text's length can be asked for first.
TEST_F(CApi, TooSmallBuffers) {
  create();
  const size_t P = particles();
  size_t dim = 0;
  ASSERT_EQ(nsf_runtime_latent_dim(rom_, &dim), NSF_OK);
  std::vector<float> buffer(9 * P, -7.0f);
  const auto small = [&](nsf_status s, size_t needed) {
    EXPECT_EQ(s, NSF_ERROR_BUFFER_TOO_SMALL) << nsf_status_name(s);
    EXPECT_NE(last_error().find(std::to_string(needed) + " are needed"), std::string::npos)
        << last_error();
    for (float f : buffer) ASSERT_EQ(f, -7.0f) << "a refused call wrote into the buffer";
  };
  small(nsf_runtime_positions(rom_, buffer.data(), 3 * P - 1), 3 * P);
  small(nsf_runtime_velocities(rom_, buffer.data(), 0), 3 * P);
  small(nsf_runtime_stress(rom_, buffer.data(), 3 * P), 9 * P);
  small(nsf_runtime_latent(rom_, buffer.data(), dim - 1), dim);
  EXPECT_EQ(last_error().rfind("nsf_runtime_latent: the buffer holds ", 0), 0u) << last_error();

  size_t length = 0;
  ASSERT_EQ(nsf_runtime_collider_type(rom_, 0, nullptr, 0, &length), NSF_OK);
  EXPECT_EQ(length, 5u);  // "plane"
  char text[5] = {'x', 'x', 'x', 'x', 'x'};
  length = 0;
  EXPECT_EQ(nsf_runtime_collider_type(rom_, 0, text, sizeof text, &length),
            NSF_ERROR_BUFFER_TOO_SMALL);
  EXPECT_EQ(length, 5u);
  EXPECT_EQ(std::string(text, 5), "xxxxx");
  EXPECT_NE(last_error().find("6 are needed"), std::string::npos) << last_error();
  EXPECT_EQ(nsf_runtime_collider_type(rom_, 0, text, 0, &length), NSF_ERROR_BUFFER_TOO_SMALL)
      << "size 0 with a buffer is too small, not a length query";
}

// A model or scene that is not there is NSF_ERROR_FILE_NOT_FOUND naming it; a file that is no
// model is NSF_ERROR_SETUP; *out is NULL either way.
TEST_F(CApi, MissingOrWrongFiles) {
  const nsf_runtime_options o = options();
  const std::string missing = (root_ / "no_such_model.nsf").string();
  nsf_runtime* rom = nullptr;
  EXPECT_EQ(nsf_runtime_create(missing.c_str(), kScene.c_str(), &o, &rom),
            NSF_ERROR_FILE_NOT_FOUND);
  EXPECT_EQ(rom, nullptr);
  EXPECT_EQ(last_error(), "nsf_runtime_create: the model file '" + missing + "' does not exist");
  EXPECT_EQ(nsf_runtime_create(model().c_str(), "no/such/scene.json", &o, &rom),
            NSF_ERROR_FILE_NOT_FOUND);
  EXPECT_NE(last_error().find("scene file 'no/such/scene.json'"), std::string::npos);
  EXPECT_EQ(nsf_runtime_create(root_.c_str(), kScene.c_str(), &o, &rom), NSF_ERROR_FILE_NOT_FOUND);
  EXPECT_NE(last_error().find("is a directory"), std::string::npos) << last_error();
  // The scene given as the model: there, but no model.
  EXPECT_EQ(nsf_runtime_create(kScene.c_str(), kScene.c_str(), &o, &rom), NSF_ERROR_SETUP);
  EXPECT_EQ(rom, nullptr);
  EXPECT_NE(last_error().find(kScene), std::string::npos) << last_error();
}

// Options the runtime refuses: an override naming no key of the scene, or with no '=', μ missing
// for a scene with a sweep (NSF_ERROR_SETUP); a negative count, μ or a limit not a number
// (NSF_ERROR_INVALID_ARGUMENT). The message names the problem.
TEST_F(CApi, BadOverridesAndOptions) {
  nsf_runtime* rom = nullptr;
  const auto refused = [&](const nsf_runtime_options& o, nsf_status want, const std::string& says) {
    EXPECT_EQ(nsf_runtime_create(model().c_str(), kScene.c_str(), &o, &rom), want)
        << nsf_status_name(want) << ": " << last_error();
    EXPECT_EQ(rom, nullptr);
    EXPECT_NE(last_error().find(says), std::string::npos) << last_error();
    EXPECT_EQ(last_error().rfind("nsf_runtime_create: ", 0), 0u) << last_error();
  };
  nsf_runtime_options o = options();
  const char* no_key[] = {"simulation.no_such_key=3"};
  o.overrides = no_key;
  o.override_count = 1;
  refused(o, NSF_ERROR_SETUP, "no_such_key");
  const char* no_value[] = {"simulation.frames"};
  o.overrides = no_value;
  refused(o, NSF_ERROR_SETUP, "simulation.frames");

  o = options();
  o.has_mu = 0;
  refused(o, NSF_ERROR_SETUP, "mu");
  o = options();
  o.threads = -1;
  refused(o, NSF_ERROR_INVALID_ARGUMENT, "threads");
  o = options();
  o.samples = -3;
  refused(o, NSF_ERROR_INVALID_ARGUMENT, "samples");
  o = options();
  o.mu = std::nan("");
  refused(o, NSF_ERROR_INVALID_ARGUMENT, "mu");
  o = options();
  o.indicator_courant = 0;
  refused(o, NSF_ERROR_INVALID_ARGUMENT, "indicator_courant");

  // A good override applies: the scene's frames.
  o = options();
  const char* frames[] = {"simulation.frames=5"};
  o.overrides = frames;
  o.override_count = 1;
  create(o);
  int n = 0;
  ASSERT_EQ(nsf_runtime_frame_count(rom_, &n), NSF_OK);
  EXPECT_EQ(n, 5);
}

// Errors from deep inside (a refused pose, an index past the end, latent dynamics that diverge
// with recover off) come back as codes with messages, never as exceptions; the last error is the
// calling thread's own and cleared by the next call that succeeds.
TEST_F(CApi, NoExceptionEscapes) {
  create();
  nsf_collider_pose pose;
  ASSERT_EQ(nsf_runtime_collider_pose(rom_, 0, &pose), NSF_OK);
  EXPECT_EQ(last_error(), "");

  nsf_collider_pose bad = pose;
  bad.position[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NO_THROW(
      EXPECT_EQ(nsf_runtime_set_collider_pose(rom_, 0, &bad), NSF_ERROR_INVALID_ARGUMENT));
  EXPECT_NE(last_error().find("not finite"), std::string::npos) << last_error();
  bad = pose;
  bad.rotation[0] = 2;
  EXPECT_EQ(nsf_runtime_set_collider_pose(rom_, 0, &bad), NSF_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(last_error().find("not a rotation"), std::string::npos) << last_error();
  bad = pose;
  bad.position[1] = 1e6;
  EXPECT_EQ(nsf_runtime_set_collider_pose(rom_, 0, &bad), NSF_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(nsf_runtime_set_collider_pose(rom_, 3, &pose), NSF_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(last_error(),
            "nsf_runtime_set_collider_pose: collider 3 does not exist: the scene has 1");
  EXPECT_EQ(nsf_runtime_collider_pose(rom_, 1, &pose), NSF_ERROR_INVALID_ARGUMENT);
  size_t length = 0;
  EXPECT_EQ(nsf_runtime_collider_type(rom_, 1, nullptr, 0, &length), NSF_ERROR_INVALID_ARGUMENT);

  // The last error belongs to the thread that made it.
  std::string elsewhere = "unset";
  std::thread([&] { elsewhere = nsf_last_error(); }).join();
  EXPECT_EQ(elsewhere, "");
  EXPECT_NE(last_error(), "");
  double t = 0;
  ASSERT_EQ(nsf_runtime_time(rom_, &t), NSF_OK);
  EXPECT_EQ(last_error(), "");

  // A Courant limit no step keeps: with recover off the step is kept and flagged, with it on
  // the step is redone, and the health says so, with the text.
  nsf_runtime_destroy(rom_);
  rom_ = nullptr;
  nsf_runtime_options strict = options();
  strict.indicator_courant = 1e-12;
  strict.recover = 0;
  create(strict);
  nsf_health h;
  ASSERT_EQ(nsf_runtime_step(rom_), NSF_OK) << last_error();
  ASSERT_EQ(nsf_runtime_health(rom_, &h), NSF_OK);
  EXPECT_EQ(h.flagged, 1);
  EXPECT_EQ(h.recoveries, 0);
  nsf_runtime_destroy(rom_);
  rom_ = nullptr;
  strict.recover = 1;
  create(strict);
  ASSERT_EQ(nsf_runtime_step(rom_), NSF_OK) << last_error();
  ASSERT_EQ(nsf_runtime_health(rom_, &h), NSF_OK);
  EXPECT_EQ(h.flagged, 1);
  EXPECT_GE(h.recoveries, 1);
  ASSERT_EQ(nsf_runtime_last_recovery(rom_, nullptr, 0, &length), NSF_OK);
  ASSERT_GT(length, 0u);
  std::vector<char> text(length + 1, 'x');
  ASSERT_EQ(nsf_runtime_last_recovery(rom_, text.data(), text.size(), &length), NSF_OK);
  EXPECT_EQ(std::strlen(text.data()), length);
  EXPECT_NE(std::string(text.data()).find("Courant"), std::string::npos) << text.data();

  // Thrown 20 m/s sideways, far past the training runs' 0.5-1.5: the latent dynamics diverge
  // (a point off the grid). Recover off: the frame fails with the reason, and no exception.
  nsf_runtime_destroy(rom_);
  rom_ = nullptr;
  nsf_runtime_options wild = options();
  wild.mu = 20;
  wild.recover = 0;
  create(wild);
  nsf_status status = NSF_OK;
  for (int frame = 0; frame < 12 && status == NSF_OK; ++frame)
    EXPECT_NO_THROW(status = nsf_runtime_advance_frame(rom_));
  EXPECT_EQ(status, NSF_ERROR_STEP) << nsf_status_name(status);
  EXPECT_EQ(last_error().rfind("nsf_runtime_advance_frame: ", 0), 0u) << last_error();
  EXPECT_NE(last_error().find("diverged"), std::string::npos) << last_error();
}

// The header as C99 compiles it (tests/unit/runtime/c_api_c99.c, -std=c99 -pedantic -Werror) runs
// the model.
TEST_F(CApi, FromC99) {
  char message[512];
  EXPECT_EQ(nsf_test_c99_run(model().c_str(), kScene.c_str(), message, sizeof message), NSF_OK)
      << message;
  EXPECT_EQ(nsf_test_c99_run("missing.nsf", kScene.c_str(), message, sizeof message),
            NSF_ERROR_FILE_NOT_FOUND);
  EXPECT_NE(std::string(message).find("missing.nsf"), std::string::npos) << message;
}

}  // namespace
