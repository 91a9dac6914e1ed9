// Training and inference throughput of the networks (docs/BENCHMARKS.md, "Neural fields"):
// points per second through one decoder for an Adam step on a batch (what `nsf train` does in
// stages 1–3) and for batched no-grad inference (what the ROM does on N every step), and frames
// per second through the encoder. Synthetic inputs: the cost depends on the shapes only.
//   build/nn_throughput [--benchmark_filter=...]   (NSF_THREADS=1 for one thread; default 2)
#include <benchmark/benchmark.h>
#include <torch/torch.h>

#include <malloc.h>

#include <cstdlib>
#include <string>

#include "nn/latent_inversion.h"
#include "nn/model/neural_model.h"
#include "nn/network_samples.h"
#include "nn/networks.h"
#include "nn/torch_settings.h"

namespace {

constexpr int64_t kDepth = 5, kLatent = 6, kBatch = 2048;  // 4 frames × 512 particles

// Output sizes of g, h, l; h also takes μ.
int64_t out_of(int net) {
  return net == 0 ? 3 : net == 1 ? 6 : 9;
}
int64_t in_of(int net) {
  return 3 + kLatent + (net == 1 ? 1 : 0);
}
const char* name_of(int net) {
  return net == 0 ? "g" : net == 1 ? "h" : "l";
}

void adam_steps(benchmark::State& state) {
  const int net = int(state.range(0));
  const int64_t width = state.range(1);
  torch::manual_seed(1);
  nsf::FieldMlp mlp(in_of(net), out_of(net), width, kDepth);
  torch::optim::Adam adam(mlp->parameters(), torch::optim::AdamOptions(1e-3));
  const torch::Tensor in = torch::randn({kBatch, in_of(net)});
  const torch::Tensor target = torch::randn({kBatch, out_of(net)});
  for (auto _ : state) {
    adam.zero_grad();
    const torch::Tensor loss = torch::mse_loss(mlp->forward(in), target);
    loss.backward();
    adam.step();
    benchmark::DoNotOptimize(loss.data_ptr<float>());
  }
  state.SetItemsProcessed(state.iterations() * kBatch);
  state.SetLabel(std::string(name_of(net)) + " width " + std::to_string(width));
}

// The same Adam step with glibc's default allocator (a dynamic mmap threshold, freed heap tops
// trimmed) and with nsf's (nsf::retain_freed_memory), side by side in one run. The settings are
// process-wide and cannot be undone, so the default cases are registered first and every other
// benchmark starts by switching to nsf's.
void train_step(benchmark::State& state) {
  nsf::retain_freed_memory();
  adam_steps(state);
}

void train_step_allocator(benchmark::State& state) {
  const bool retain = state.range(2) != 0;
  if (retain) nsf::retain_freed_memory();
  adam_steps(state);
  state.SetLabel(std::string(name_of(int(state.range(0)))) + " width " +
                 std::to_string(state.range(1)) +
                 (retain ? ", nsf allocator" : ", glibc default allocator"));
}

void inference(benchmark::State& state) {
  const int net = int(state.range(0));
  nsf::retain_freed_memory();
  const int64_t width = state.range(1), points = state.range(2);
  torch::manual_seed(1);
  nsf::FieldMlp mlp(in_of(net), out_of(net), width, kDepth);
  const torch::Tensor in = torch::randn({points, in_of(net)});
  torch::NoGradGuard no_grad;
  for (auto _ : state) {
    const torch::Tensor out = mlp->forward(in);
    benchmark::DoNotOptimize(out.data_ptr<float>());
  }
  state.SetItemsProcessed(state.iterations() * points);
  state.SetLabel(std::string(name_of(net)) + " width " + std::to_string(width));
}

void encoder_frames(benchmark::State& state) {
  nsf::retain_freed_memory();
  const int64_t particles = state.range(0), max_length = state.range(1), frames = 4;
  torch::manual_seed(1);
  nsf::Encoder e(particles, kLatent, 32, 3, max_length);
  const torch::Tensor x = torch::randn({frames, 3 * particles});
  for (auto _ : state) {
    const torch::Tensor z = e->forward(x);
    z.sum().backward();
    benchmark::DoNotOptimize(z.data_ptr<float>());
  }
  state.SetItemsProcessed(state.iterations() * frames);
  state.SetLabel("forward + backward, " + std::to_string(particles) + " particles, max length " +
                 std::to_string(max_length));
}

// Refining training frames' latents before stages 2 and 3 (nsf train --refine-latents): frame
// by frame on the pool's BLAS threads (range 0 = 0, as nsf train did before 2026-11-24) against
// FrameLatentRefiner::refine_many, one frame per thread (1). The jelly's shapes: 5,056
// particles, r = 5, g width 192; targets are g at a random latent plus noise, starts at 0.
void refine_frames(benchmark::State& state) {
  nsf::retain_freed_memory();
  const bool many = state.range(0) != 0;
  const int64_t particles = 5056, frames = 8;
  torch::manual_seed(1);
  nsf::NetConfig c;
  c.latent_dim = 5, c.width_g = 192;
  std::vector<nsf::Vec3> X(particles);
  const torch::Tensor Xt = torch::rand({particles, 3}, torch::kFloat64);
  for (int64_t p = 0; p < particles; ++p)
    X[p] = nsf::Vec3(Xt[p][0].item<double>(), Xt[p][1].item<double>(), Xt[p][2].item<double>());
  nsf::NeuralModel model(c, nsf::SceneFingerprint::of("bench", X), false);
  const nsf::FrameLatentRefiner refiner(model, X, 10);
  std::vector<std::vector<float>> x(frames);
  for (auto& f : x) {
    torch::NoGradGuard no_grad;
    const torch::Tensor z = torch::randn({1, c.latent_dim}).expand({particles, c.latent_dim});
    const torch::Tensor g =
        model.deform(Xt.to(torch::kFloat32), z) + 0.01 * torch::randn({particles, 3});
    f.assign(g.data_ptr<float>(), g.data_ptr<float>() + 3 * particles);
  }
  std::vector<const float*> xs;
  for (const auto& f : x) xs.push_back(f.data());
  for (auto _ : state) {
    std::vector<Eigen::VectorXd> z(frames, Eigen::VectorXd::Zero(c.latent_dim));
    if (many) {
      refiner.refine_many(xs, z);
    } else {
      for (int64_t k = 0; k < frames; ++k) z[k] = refiner.refine(x[k].data(), z[k]);
    }
    benchmark::DoNotOptimize(z.back().data());
  }
  state.SetItemsProcessed(state.iterations() * frames);
  state.SetLabel(many ? "refine_many, one frame per thread"
                      : "frame by frame, GEMMs on the pool's threads");
}

// Table 1's widths (β·d) of the scenes, and the 128 that `nsf report` and `nsf demo` use.
void widths(benchmark::internal::Benchmark* b) {
  for (int64_t w : {96, 144}) b->Args({0, w});
  for (int64_t w : {128, 288, 384, 432}) b->Args({1, w});
  for (int64_t w : {128, 432, 576, 648}) b->Args({2, w});
}

void inference_widths(benchmark::internal::Benchmark* b) {
  for (int64_t w : {96, 144}) b->Args({0, w, 8192});
  for (int64_t w : {128, 384}) b->Args({1, w, 8192});
  for (int64_t w : {128, 576}) b->Args({2, w, 8192});
}

}  // namespace

BENCHMARK(train_step_allocator)
    ->Args({0, 192, 0})
    ->Args({1, 128, 0})
    ->Args({0, 192, 1})
    ->Args({1, 128, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(train_step)->Apply(widths)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(inference)->Apply(inference_widths)->Unit(benchmark::kMillisecond)->UseRealTime();
// App. E's stop at length 12, and the 1024 that the jelly trains with (docs/TRAINING.md).
BENCHMARK(encoder_frames)
    ->Args({5000, 12})
    ->Args({5000, 1024})
    ->Args({50000, 12})
    ->Args({50000, 1024})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK(refine_frames)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

int main(int argc, char** argv) {
  const char* t = std::getenv("NSF_THREADS");
  const int threads = nsf::set_nn_threads(t ? std::atoi(t) : 2, /*retain_memory=*/false);
  benchmark::Initialize(&argc, argv);
  benchmark::AddCustomContext("gemm_threads", std::to_string(threads));
  benchmark::AddCustomContext("blas", nsf::blas_info());
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
