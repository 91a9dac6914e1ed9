// The runtime's MLP plugin (libnsf_mlp.so): an MLP model run by nsf::Runtime, which evaluates its
// networks through the plugin's C table, against the tool's reduced-order stepper (NeuralFields
// loaded with LibTorch, as `nsf rom` loads it) on the same model, scene and settings; and the
// error a host gets when the plugin is missing. The build tree's plugin lies beside
// libnsf_runtime.so, where the runtime looks for it.
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <nsf/runtime.h>
#include <stdlib.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "error_matchers.h"
#include "nn/neural_fields.h"
#include "rom/setup/rom_setup.h"
#include "rom/step/latent_stepper.h"
#include "tiny_mlp_model.h"

namespace {

namespace fs = std::filesystem;

class MlpRuntime : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = nsf::testing::fresh_dir("mlp_runtime");
    model_ = nsf::testing::train_tiny_mlp(root_, log_);
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }
  void SetUp() override {
    ASSERT_FALSE(model_.empty()) << "training the tiny MLP model failed:\n" << log_;
  }

  static nsf::RuntimeOptions options() {
    nsf::RuntimeOptions o;
    o.mu = 1.0;
    o.threads = 2;
    return o;
  }

  static inline fs::path root_;
  static inline std::string model_, log_;
};

// Sets an environment variable for one scope.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = getenv(name)) old_ = std::make_unique<std::string>(old);
    setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (old_)
      setenv(name_, old_->c_str(), 1);
    else
      unsetenv(name_);
  }

 private:
  const char* name_;
  std::unique_ptr<std::string> old_;
};

// The message of the std::runtime_error, the one type nsf::Runtime throws to a host, that
// constructing a runtime of `model` must throw.
std::string setup_error(const std::string& model) {
  try {
    nsf::RuntimeOptions o;
    o.mu = 1.0;
    nsf::Runtime rt(model, nsf::testing::rom_tiny_scene(), o);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  ADD_FAILURE() << "the runtime was made";
  return "";
}

TEST_F(MlpRuntime, StepsAsTheToolsStepperDoesOverSeveralFrames) {
  unsetenv("NSF_MLP_PLUGIN");
  const std::string scene = nsf::testing::rom_tiny_scene();
  nsf::Runtime rt(model_, scene, options());

  // The tool's stepper: the model loaded with LibTorch, the same set-up.
  nsf::NeuralFields fields = nsf::NeuralFields::load(model_);
  ASSERT_EQ(fields.family(), nsf::DecoderFamily::mlp);
  nsf::RomSetup s = nsf::rom_setup(fields, scene, 1.0, {}, 0);
  nsf::LatentStepper tool(fields, std::move(s.scene), s.mu, s.options);
  ASSERT_EQ(rt.particle_count(), tool.particle_count());
  ASSERT_EQ(rt.steps_per_frame(), tool.steps_per_frame());

  // The latent networks run in float on both sides; the runtime's own Eigen (its x86-64-v3 copy
  // on a CPU with AVX2) rounds otherwise than the test's: 1e-4 m over 6 frames of a bar 0.4 m long.
  const float tolerance = 1e-4f;
  float worst = 0, moved = 0;
  std::vector<nsf::Vec3> x0;
  tool.particle_state(x0, nullptr);
  for (int frame = 1; frame <= 6; ++frame) {
    rt.advance_frame();
    tool.advance_frame();
    std::vector<nsf::Vec3> x;
    tool.particle_state(x, nullptr);
    const std::vector<float> y = rt.positions();
    ASSERT_EQ(y.size(), 3 * x.size());
    for (size_t p = 0; p < x.size(); ++p)
      for (int k = 0; k < 3; ++k) {
        worst = std::max(worst, std::abs(y[3 * p + k] - float(x[p][k])));
        moved = std::max(moved, float(std::abs(x[p][k] - x0[p][k])));
      }
    EXPECT_LE(worst, tolerance) << "frame " << frame;
  }
  EXPECT_EQ(rt.health().recoveries, 0) << "the runtime redid a step the tool's stepper kept";
  EXPECT_GT(moved, 10 * tolerance) << "the bar did not move: the comparison shows nothing";
  std::printf("runtime vs the tool's stepper over 6 frames: %.3g m at most (moved %.3g m)\n",
              double(worst), double(moved));
  // The encoder's latent of the rest state, as the plugin evaluates it, starts both runs.
  std::vector<float> z(rt.latent_dim());
  rt.latent(z.data(), z.size());
  for (size_t k = 0; k < z.size(); ++k) EXPECT_TRUE(std::isfinite(z[k]));
}

TEST_F(MlpRuntime, AMissingPluginIsAnErrorNamingTheModelAndWhereItLooked) {
  const std::string missing = (root_ / "nowhere" / "libnsf_mlp.so").string();
  const ScopedEnv env("NSF_MLP_PLUGIN", missing);
  const std::string why = setup_error(model_);
  for (const std::string& part :
       {model_, missing, std::string("no such file"), std::string("NSF_MLP_PLUGIN"),
        std::string("LibTorch"), std::string("MLP model")})
    nsf::testing::expect_contains(why, part);
}

TEST_F(MlpRuntime, ALibraryThatIsNoPluginIsRefusedSayingWhy) {
  // A shared library without the plugin's table: the runtime itself.
  Dl_info info{};
  ASSERT_NE(dladdr(reinterpret_cast<void*>(&nsf::version), &info), 0);
  const std::string runtime = info.dli_fname;
  const ScopedEnv env("NSF_MLP_PLUGIN", runtime);
  nsf::testing::expect_contains(setup_error(model_),
                                runtime + ": it has no nsf_mlp_plugin_table table");
}

}  // namespace
