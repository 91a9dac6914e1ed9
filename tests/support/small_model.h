#pragma once
// A small, untrained model of either family on 40 particles (the scene "fuzz"), built in memory:
// the model file's tests write, damage and load it (unit/rom/test_rom_fuzz_model.cpp,
// test_rom_calibration_record.cpp).
#include <torch/torch.h>

#include <string>
#include <vector>

#include "core/types.h"
#include "nn/model/neural_model.h"

namespace nsf::testing {

inline constexpr int kSmallModelParticles = 40;

inline std::vector<nsf::Vec3> small_model_rest_positions() {
  std::vector<nsf::Vec3> X;
  for (int p = 0; p < kSmallModelParticles; ++p)
    X.emplace_back(0.1 * (p % 4), 0.1 * (p / 4 % 5), 0.05 * p);
  return X;
}

// A model of kSmallModelParticles particles, untrained (its weights are the initial ones): the
// loader sees the same entries as in a trained one.
inline nsf::NeuralModel small_model(const std::string& decoder) {
  nsf::NetConfig c;
  c.decoder = nsf::parse_family(decoder, "the test's decoder");
  c.latent_dim = 2;
  c.depth = 2;
  c.width_g = c.width_h = c.width_l = 8;
  c.encoder_hidden = 8;
  c.coefficient_width = 8;
  c.coefficient_depth = 2;
  c.modes = {2, 3, 3};
  const std::vector<nsf::Vec3> X = small_model_rest_positions();
  nsf::NeuralModel m(c, nsf::SceneFingerprint::of("fuzz", X), /*has_mu=*/true);
  m.mu_min = 1;
  m.mu_max = 2;
  m.rest = torch::zeros({kSmallModelParticles, 3});
  for (int p = 0; p < kSmallModelParticles; ++p)
    for (int k = 0; k < 3; ++k) m.rest[p][k] = float(X[size_t(p)][k]);
  const int64_t dims[3] = {3, 6, 9};
  if (decoder == "basis")
    for (int f = 0; f < 3; ++f) {
      m.basis[f].mean = torch::zeros({kSmallModelParticles, dims[f]});
      m.basis[f].modes = torch::randn({kSmallModelParticles, dims[f], c.modes[f]});
      m.basis[f].scale = torch::ones({c.modes[f]});
    }
  if (decoder == "basis") {  // C's coefficient map (the default): 8 centres of (ẑ, μ, ż)
    const int64_t d = 2 * c.latent_dim + 1, K = c.modes[2];
    const auto f64 = torch::TensorOptions().dtype(torch::kFloat64);
    nsf::BasisField& b = m.basis[2];
    b.map_centers = torch::randn({8, d}, f64), b.map_weights = torch::randn({8, K}, f64);
    b.map_poly = torch::randn({d + 1, K}, f64);
    b.map_shift = torch::zeros({d}, f64), b.map_scale = torch::ones({d}, f64);
  }
  m.trajectory_latents = torch::zeros({2, 3, c.latent_dim});
  m.trajectory_mu = torch::tensor({1.0f, 2.0f});
  return m;
}

}  // namespace nsf::testing
