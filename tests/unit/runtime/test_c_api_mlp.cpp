// An MLP model through the C API (include/nsf/nsf.h): libnsf_runtime.so opens its MLP plugin
// (libnsf_mlp.so, beside it in the build tree) for it, and gives the positions nsf::Runtime gives;
// with the plugin missing, nsf_runtime_create returns NSF_ERROR_SETUP and says what to do, and
// no handle. The comparison with the tool's own stepper is tests/app/test_app_mlp_runtime.cpp's.
#include <gtest/gtest.h>
#include <nsf/nsf.h>
#include <nsf/runtime.h>
#include <stdlib.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "c_api_options.h"
#include "tiny_mlp_model.h"

namespace {

namespace fs = std::filesystem;

class CApiMlp : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = nsf::testing::fresh_dir("c_api_mlp");
    model_ = nsf::testing::train_tiny_mlp(root_, log_);
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }
  void SetUp() override {
    ASSERT_FALSE(model_.empty()) << "training the tiny MLP model failed:\n" << log_;
    unsetenv("NSF_MLP_PLUGIN");
  }
  void TearDown() override {
    nsf_runtime_destroy(rom_);
    unsetenv("NSF_MLP_PLUGIN");
  }
  static nsf_runtime_options options() { return nsf::testing::tiny_c_api_options(); }

  static inline fs::path root_;
  static inline std::string model_, log_;
  nsf_runtime* rom_ = nullptr;
};

TEST_F(CApiMlp, RunsAnMlpModelAsTheCppApiDoes) {
  const nsf_runtime_options o = options();
  const std::string scene = nsf::testing::rom_tiny_scene();
  ASSERT_EQ(nsf_runtime_create(model_.c_str(), scene.c_str(), &o, &rom_), NSF_OK)
      << nsf_last_error();
  nsf::RuntimeOptions co;
  co.mu = 1.0;
  co.threads = 2;
  nsf::Runtime cpp(model_, scene, co);
  size_t n = 0;
  ASSERT_EQ(nsf_runtime_particle_count(rom_, &n), NSF_OK);
  ASSERT_EQ(n, cpp.particle_count());
  std::vector<float> x(3 * n), x0(3 * n);
  ASSERT_EQ(nsf_runtime_positions(rom_, x0.data(), x0.size()), NSF_OK);
  float moved = 0;
  for (int frame = 1; frame <= 4; ++frame) {
    ASSERT_EQ(nsf_runtime_advance_frame(rom_), NSF_OK) << nsf_last_error();
    cpp.advance_frame();
    ASSERT_EQ(nsf_runtime_positions(rom_, x.data(), x.size()), NSF_OK);
    // The same library, model and steps: the same positions (as test_c_api.cpp's basis run).
    const std::vector<float> want = cpp.positions();
    ASSERT_EQ(want.size(), x.size());
    for (size_t i = 0; i < x.size(); ++i) ASSERT_NEAR(x[i], want[i], 1e-6f) << "frame " << frame;
  }
  for (size_t i = 0; i < x.size(); ++i) {
    ASSERT_TRUE(std::isfinite(x[i]));
    moved = std::max(moved, std::abs(x[i] - x0[i]));
  }
  EXPECT_GT(moved, 1e-4f) << "the material did not move";
  // The decoder's fields come through the plugin too.
  std::vector<float> tau(9 * n), C(9 * n);
  EXPECT_EQ(nsf_runtime_stress(rom_, tau.data(), tau.size()), NSF_OK) << nsf_last_error();
  EXPECT_EQ(nsf_runtime_affine(rom_, C.data(), C.size()), NSF_OK) << nsf_last_error();
  EXPECT_TRUE(std::all_of(tau.begin(), tau.end(), [](float v) { return std::isfinite(v); }));
}

TEST_F(CApiMlp, AMissingPluginIsASetupErrorThatSaysWhatToDo) {
  const std::string missing = (root_ / "nowhere" / "libnsf_mlp.so").string();
  setenv("NSF_MLP_PLUGIN", missing.c_str(), 1);
  const nsf_runtime_options o = options();
  EXPECT_EQ(nsf_runtime_create(model_.c_str(), nsf::testing::rom_tiny_scene().c_str(), &o, &rom_),
            NSF_ERROR_SETUP);
  EXPECT_EQ(rom_, nullptr);
  const std::string why = nsf_last_error();
  for (const std::string& part : {std::string("nsf_runtime_create: "), model_, missing,
                                  std::string("NSF_MLP_PLUGIN"), std::string("cmake --install")})
    EXPECT_NE(why.find(part), std::string::npos) << "no '" << part << "' in: " << why;
}

}  // namespace
