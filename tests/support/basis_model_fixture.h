#pragma once
// A per-point basis model trained once per test process (SetUpTestSuite) on the synthetic dataset
// of nn_fixtures.h, and every field it gives at one frame, for bitwise comparisons: the fixture of
// BasisModel, whose tests are unit/nn/test_nn_basis.cpp's and cli/test_nn_basis_cli.cpp's
// (`nsf upgrade`).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "nn/dataset.h"
#include "nn/neural_fields.h"
#include "nn/torch_settings.h"
#include "nn/train/trainer.h"
#include "nn_fixtures.h"

namespace nsf::testing::basis {

namespace fs = std::filesystem;

inline constexpr int kParticles = 300;

inline nsf::TrainOptions basis_options() {
  nsf::TrainOptions o;
  nsf::TrainConfig& c = o.config;
  c.net.latent_dim = 2;
  c.net.encoder_hidden = 16;
  c.net.decoder = nsf::DecoderFamily::basis;
  c.net.modes = {4, 4, 4};
  c.net.coefficient_width = 32;
  c.net.coefficient_depth = 2;
  c.steps = {2000, 1000, 1000};
  c.frames_per_batch = {4, 8, 8};
  c.checkpoint_every = 50;
  c.refine_latents = 3;
  c.seed = 3;
  c.quiet = true;
  return o;
}

// Every field of a model at every particle of one frame, and at two points between particles.
// torch_free: loaded from the file's run-time record (the runtime's way), with the latent of the
// same frame encoded by the full model.
inline std::vector<double> outputs(const std::string& model, const std::string& data,
                                   bool torch_free = false) {
  const nsf::Dataset d(data);
  const Latent z = NeuralFields::load(model).encode(d.read_positions(d.test()[0], 5));
  NeuralFields nf = torch_free ? NeuralFields::load_basis(model) : NeuralFields::load(model);
  std::vector<Vec3> X = d.rest_positions();
  X.push_back(Vec3(0.5, 0.5, 0.5)), X.push_back(Vec3(0.4, 0.6, 0.3));
  const NeuralFields::Points all = nf.prepare(d.rest_positions()), extra = nf.prepare(X);
  const Latent zdot = nf.bases()->latent_velocity(z, d.read_field(d.test()[0], 5, "v").data());
  std::vector<double> out(z.data(), z.data() + z.size());
  for (const NeuralFields::Points* pts : {&all, &extra}) {
    std::vector<Vec3> x;
    std::vector<nsf::Mat3> tau, C;
    nf.deform(*pts, z, x);
    nf.stress(*pts, z, d.test()[0].mu, tau, &zdot);
    nf.affine(*pts, z, C, d.test()[0].mu, &zdot);
    for (const Vec3& v : x) out.insert(out.end(), v.data(), v.data() + 3);
    for (const auto& m : tau) out.insert(out.end(), m.data(), m.data() + 9);
    for (const auto& m : C) out.insert(out.end(), m.data(), m.data() + 9);
  }
  return out;
}

class BasisModel : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    nsf::set_nn_threads(2);
    root_ = fs::temp_directory_path() / ("nsf_basis_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    nsf::test::write_synthetic_dataset(root_ / "data", kParticles);
    report_ = nsf::train_model(data(), model(), basis_options());
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }
  static std::string data() { return (root_ / "data").string(); }
  static std::string model() { return (root_ / "basis.nsf").string(); }
  inline static fs::path root_;
  inline static nsf::TrainReport report_;
};

}  // namespace nsf::testing::basis
