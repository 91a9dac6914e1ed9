#include <gtest/gtest.h>

#include <cmath>

#include "nn/config.h"
#include "nn/networks.h"
#include "nn/torch_settings.h"

using nsf::Encoder;
using nsf::FieldMlp;

namespace {

// Conv1d(kernel 6, stride 4) until the length is ≤ 12 (App. E): the expected layer count and the
// flattened size reaching the first Linear, computed independently of the module.
std::pair<int64_t, int64_t> expected_encoder_shape(int64_t particles) {
  int64_t length = 3 * particles, layers = 0;
  while (length > 12) length = (length - 6) / 4 + 1, ++layers;
  return {layers, (layers ? 3 : 1) * length};
}

}  // namespace

TEST(NnEncoder, OutputShapeForSeveralParticleCounts) {
  torch::manual_seed(0);
  for (int64_t P : {1, 4, 5, 100, 1000, 12345}) {
    for (int64_t r : {5, 6}) {
      Encoder e(P, r);
      const auto [layers, flat] = expected_encoder_shape(P);
      EXPECT_EQ(e->conv_layers(), layers) << P;
      EXPECT_EQ(e->flat_length(), flat) << P;
      const torch::Tensor z = e->forward(torch::randn({3, 3 * P}));
      ASSERT_EQ(z.dim(), 2);
      EXPECT_EQ(z.size(0), 3);
      EXPECT_EQ(z.size(1), r);
      EXPECT_TRUE(torch::isfinite(z).all().item<bool>());
    }
  }
  // The documented sizes: 12345 particles → 37035 → 9258 → 2314 → 577 → 143 → 35 → 8.
  EXPECT_EQ(Encoder(12345, 6)->conv_layers(), 6);
  EXPECT_EQ(Encoder(12345, 6)->flat_length(), 24);
}

// Wider convolutions (--encoder-channels) keep the layer count and widen the flattened features;
// the jelly's 5,056 particles end at length 3, so App. E's 3 channels leave 9 features.
TEST(NnEncoder, ChannelsWidenTheFlattenedFeatures) {
  EXPECT_EQ(Encoder(5056, 5)->flat_length(), 9);
  Encoder wide(5056, 5, /*hidden=*/128, /*channels=*/8);
  EXPECT_EQ(wide->conv_layers(), Encoder(5056, 5)->conv_layers());
  EXPECT_EQ(wide->flat_length(), 24);
  EXPECT_EQ(wide->forward(torch::randn({2, 3 * 5056})).size(1), 5);
  EXPECT_ANY_THROW(Encoder(100, 5, 32, 0));
}

// --encoder-max-length stops the convolutions earlier: with 48 the jelly's 5,056 particles go
// 15168 → 3791 → 947 → 236 → 58 → 14 (five layers, not six), so 3 channels leave 42 features.
TEST(NnEncoder, MaxLengthStopsTheConvolutionsEarlier) {
  Encoder e(5056, 5, /*hidden=*/32, /*channels=*/3, /*max_length=*/48);
  EXPECT_EQ(e->conv_layers(), 5);
  EXPECT_EQ(e->flat_length(), 3 * 14);
  EXPECT_EQ(e->forward(torch::randn({2, 3 * 5056})).size(1), 5);
  EXPECT_EQ(Encoder(5056, 5, 32, 3, 64)->flat_length(), 3 * 58);
  EXPECT_EQ(Encoder(5056, 5, 32, 8, 48)->flat_length(), 8 * 14);
  // No convolution at all when the input is already short enough.
  EXPECT_EQ(Encoder(10, 5, 32, 3, 30)->conv_layers(), 0);
  EXPECT_EQ(Encoder(10, 5, 32, 3, 30)->flat_length(), 30);
  EXPECT_ANY_THROW(Encoder(100, 5, 32, 3, 4));  // a length-5 input would not fill a kernel
}

TEST(NnEncoder, RejectsAnotherParticleCount) {
  Encoder e(100, 6);
  EXPECT_ANY_THROW(e->forward(torch::zeros({1, 3 * 101})));
}

TEST(NnFieldMlp, LayersWidthsAndXavierInit) {
  torch::manual_seed(0);
  const int64_t in = 9, out = 6, width = 384, depth = 5;
  FieldMlp h(in, out, width, depth);
  ASSERT_EQ(h->layers().size(), size_t(depth + 1));
  for (size_t i = 0; i < h->layers().size(); ++i) {
    const auto& w = h->layers()[i]->weight;
    const int64_t fan_in = i == 0 ? in : width, fan_out = i == size_t(depth) ? out : width;
    EXPECT_EQ(w.size(0), fan_out);
    EXPECT_EQ(w.size(1), fan_in);
    const double bound = std::sqrt(6.0 / double(fan_in + fan_out));
    EXPECT_LE(w.abs().max().item<double>(), bound + 1e-6);
    EXPECT_GT(w.abs().max().item<double>(), 0.5 * bound);  // uniform, fills its range
    EXPECT_EQ(h->layers()[i]->bias.abs().max().item<double>(), 0.0);
  }
  const torch::Tensor y = h->forward(torch::randn({1000, in}));
  EXPECT_EQ(y.size(0), 1000);
  EXPECT_EQ(y.size(1), out);
}

TEST(NnConfig, Table1DefaultsAndFallback) {
  std::string row;
  const nsf::NetConfig sand = nsf::default_net_config("sand", &row);
  EXPECT_EQ(row, "sand");
  EXPECT_EQ(sand.latent_dim, 6);
  EXPECT_EQ(sand.width_g, 48 * 3);
  EXPECT_EQ(sand.width_h, 72 * 6);
  EXPECT_EQ(sand.width_l, 72 * 9);
  EXPECT_EQ(sand.depth, 5);
  const nsf::NetConfig metal = nsf::default_net_config("metal_frame", &row);
  EXPECT_EQ(row, "metal");
  EXPECT_EQ(metal.latent_dim, 5);
  EXPECT_EQ(metal.width_h, 48 * 6);
  const nsf::NetConfig ball = nsf::default_net_config("squishy_ball", &row);
  EXPECT_EQ(ball.width_l, 72 * 9);
  nsf::default_net_config("something_else", &row);
  EXPECT_EQ(row, "default");
}

TEST(NnConfig, LearningRateStepsCoverTheStage) {
  EXPECT_EQ(nsf::learning_rate(0, 100), 1e-3);
  EXPECT_EQ(nsf::learning_rate(19, 100), 1e-3);
  EXPECT_EQ(nsf::learning_rate(20, 100), 5e-4);
  EXPECT_EQ(nsf::learning_rate(59, 100), 2e-4);
  EXPECT_EQ(nsf::learning_rate(79, 100), 1e-4);
  EXPECT_EQ(nsf::learning_rate(99, 100), 5e-5);
  EXPECT_EQ(nsf::learning_rate(2, 3), 1e-4);  // fewer steps than rates: still ends lower
}

TEST(NnRuntime, ScopedBlasThreadsRestoresTheCount) {
  if (!nsf::blas_is_openblas()) GTEST_SKIP() << "libblas.so.3 is not OpenBLAS";
  nsf::set_nn_threads(2);
  ASSERT_EQ(nsf::blas_thread_count(), 2);
  {
    const nsf::ScopedBlasThreads one(1);
    EXPECT_EQ(nsf::blas_thread_count(), 1);
  }
  EXPECT_EQ(nsf::blas_thread_count(), 2);
}
