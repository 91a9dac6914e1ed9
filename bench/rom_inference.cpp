// What one ROM step's inference costs per integration point, for each decoder family, beside
// what the full-order engine spends per particle per step, in one run, on one scene, with the
// same threads (docs/BENCHMARKS.md, "Inference per point"):
//   build/rom_inference [--scene scenes/paper/metal_small.json] [--threads 2] [--json FILE]
// Per point per step, the ROM infers x on the candidates at ẑ_n and ẑ_{n−1}, then τ and C on N;
// this times exactly those calls of the field sources (rom/fields/field_source.h) on the scene's
// first
// `--points` particles. The networks have the scene's Table 1 shapes and the bases `--modes`
// modes; their values are random, since the cost depends on the shapes alone.
#include <omp.h>
#include <torch/torch.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/timer.h"
#include "io/atomic_file.h"
#include "mpm/scene/scene.h"
#include "mpm/simulation.h"
#include "nn/basis_decoders.h"
#include "nn/config.h"
#include "nn/model/neural_model.h"
#include "nn/neural_fields.h"
#include "nn/torch_settings.h"
#include "rom/fields/field_source.h"

namespace {

struct Spread {
  double median = 0, min = 0, max = 0;
};

Spread spread_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return {v[v.size() / 2], v.front(), v.back()};
}

// A model of the scene's shapes with random weights (and random bases), saved and loaded as a
// user's model would be.
nsf::NeuralFields random_model(const nsf::Scene& scene, nsf::DecoderFamily decoder,
                               const std::array<int, 3>& modes, const std::string& path) {
  nsf::NetConfig c = nsf::default_net_config(scene.name);
  c.decoder = decoder;
  c.modes = modes;
  torch::manual_seed(1);
  nsf::NeuralModel m(c, nsf::SceneFingerprint::of(scene.name, scene.particles.X), true);
  const int64_t P = int64_t(scene.particles.size());
  m.rest = torch::from_blob(const_cast<double*>(scene.particles.X.data()->data()), {P, 3},
                            torch::kFloat64)
               .to(torch::kFloat32);
  const int64_t dims[3] = {3, 6, 9};
  for (int f = 0; f < 3 && decoder == nsf::DecoderFamily::basis; ++f) {
    m.basis[f].mean = 1e-3 * torch::randn({P, dims[f]});
    m.basis[f].modes = 1e-3 * torch::randn({P, dims[f], modes[f]});
    m.basis[f].scale = torch::ones({modes[f]});
  }
  if (c.uses_map(2)) {  // C's coefficient map (the default): 600 training rows of (ẑ, μ, ż)
    const int64_t d = 2 * c.latent_dim + 1, K = modes[2];
    const auto f64 = torch::TensorOptions().dtype(torch::kFloat64);
    nsf::BasisField& b = m.basis[2];
    b.map_centers = torch::randn({600, d}, f64), b.map_weights = 1e-3 * torch::randn({600, K}, f64);
    b.map_poly = 1e-3 * torch::randn({d + 1, K}, f64);
    b.map_shift = torch::zeros({d}, f64), b.map_scale = torch::ones({d}, f64);
  }
  m.save(path);
  return nsf::NeuralFields::load(path);
}

// Seconds per step of the ROM's inference on the points `ids`, best of `repeats` medians.
std::vector<double> time_sources(nsf::NeuralFields& fields, const nsf::Scene& scene,
                                 const std::string& source, const std::vector<uint32_t>& ids,
                                 int steps, int repeats) {
  nsf::PointTable table;
  table.particles = scene.particles.size();
  table.X = scene.particles.X, table.material = scene.particles.material;
  table.mat0 = scene.particles.mat;
  nsf::FieldContext context{fields, table, scene.materials, 1.0, scene.settings.dt, nullptr};
  auto g = nsf::make_deformation_source(source, context);
  auto h = nsf::make_point_field_source(nsf::FieldRole::stress, source, context);
  auto l = nsf::make_point_field_source(nsf::FieldRole::affine, source, context);
  nsf::Latent z = nsf::Latent::Constant(fields.latent_dim(), 0.1), z_prev = z * 0.9;
  std::vector<nsf::Vec3> x, xp;
  std::vector<nsf::Mat3> tau, C;
  std::vector<double> per_step;
  for (int rep = 0; rep <= repeats; ++rep) {  // the first round warms up
    const double t0 = nsf::now_seconds();
    for (int s = 0; s < steps; ++s) {
      z[0] += 1e-4;  // a new latent each step, as in a run
      g->positions_pair(ids, {z, z_prev}, x, xp);
      h->evaluate(ids, {z, z_prev}, true, tau);
      l->evaluate(ids, {z, z_prev}, true, C);
    }
    if (rep > 0) per_step.push_back((nsf::now_seconds() - t0) / steps);
  }
  return per_step;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app(
      "Inference per point per ROM step, MLP fields against per-point bases, beside a "
      "full-order particle update");
  std::string scene_path = std::string(NSF_SOURCE_DIR) + "/scenes/paper/metal_small.json";
  std::string json;
  int threads = 2, points = 0, steps = 20, repeats = 5;
  std::vector<int> modes = {32, 64, 64};
  app.add_option("--scene", scene_path, "Scene JSON")->capture_default_str();
  app.add_option("--threads,-j", threads, "Threads for both")->capture_default_str();
  app.add_option("--points", points, "Integration points (0 = every particle)")
      ->capture_default_str();
  app.add_option("--steps", steps, "Steps per timing")->capture_default_str();
  app.add_option("--repeat", repeats, "Timings (the spread is over these)")->capture_default_str();
  app.add_option("--modes", modes, "Basis modes of x, tau, C")->delimiter(',')->expected(3);
  app.add_option("--json", json, "Write the row here as JSON");
  CLI11_PARSE(app, argc, argv);
  omp_set_num_threads(threads);
  nsf::set_nn_threads(threads);

  nsf::Scene scene = nsf::load_scene(scene_path);
  const size_t P = scene.particles.size();
  // Full order: whole steps, per particle.
  std::vector<double> fom;
  {
    nsf::Simulation sim(nsf::load_scene(scene_path));
    for (int s = 0; s < 5; ++s) sim.step();
    for (int rep = 0; rep < repeats; ++rep) {
      const double t0 = nsf::now_seconds();
      for (int s = 0; s < steps; ++s) sim.step();
      fom.push_back((nsf::now_seconds() - t0) / steps / double(P));
    }
  }
  const size_t n = points > 0 ? std::min<size_t>(size_t(points), P) : P;
  std::vector<uint32_t> ids(n);
  for (size_t k = 0; k < n; ++k) ids[k] = uint32_t(k * P / n);
  const std::string tmp =
      (std::filesystem::temp_directory_path() / ("nsf_rom_inference_" + std::to_string(::getpid())))
          .string();
  const std::array<int, 3> K = {modes[0], modes[1], modes[2]};
  nsf::NeuralFields mlp = random_model(scene, nsf::DecoderFamily::mlp, K, tmp + "_mlp.nsf");
  nsf::NeuralFields basis = random_model(scene, nsf::DecoderFamily::basis, K, tmp + "_basis.nsf");
  std::filesystem::remove(tmp + "_mlp.nsf"), std::filesystem::remove(tmp + "_basis.nsf");
  std::vector<double> t_mlp = time_sources(mlp, scene, "network", ids, steps, repeats);
  std::vector<double> t_basis = time_sources(basis, scene, "basis", ids, steps, repeats);
  for (double& t : t_mlp) t /= double(n);
  for (double& t : t_basis) t /= double(n);

  const Spread f = spread_of(fom), m = spread_of(t_mlp), b = spread_of(t_basis);
  std::printf("scene %s: %zu particles, %zu integration points, %d threads, %d steps x %d\n",
              scene.name.c_str(), P, n, threads, steps, repeats);
  std::printf("  %-44s %9s %9s %9s %10s\n", "ns per point per step", "median", "min", "max",
              "vs full");
  auto row = [&](const char* what, const Spread& s) {
    std::printf("  %-44s %9.1f %9.1f %9.1f %9.2fx\n", what, 1e9 * s.median, 1e9 * s.min,
                1e9 * s.max, s.median / f.median);
  };
  row("full-order particle update (whole step / |P|)", f);
  row("MLP fields (g at 2 latents, h, l)", m);
  row("basis fields (g at 2 latents, h, l)", b);
  std::printf("  basis model memory: %.1f MiB of bases (K = %d, %d, %d)\n",
              double(basis.bases()->bytes()) / (1 << 20), K[0], K[1], K[2]);
  if (!json.empty()) {
    auto put = [](const Spread& s) {
      return nlohmann::json{{"median", 1e9 * s.median}, {"min", 1e9 * s.min}, {"max", 1e9 * s.max}};
    };
    nlohmann::json j = {
        {"scene", scene.name},
        {"particles", P},
        {"points", n},
        {"threads", threads},
        {"modes", modes},
        {"ns_per_point_step", {{"full_order", put(f)}, {"mlp", put(m)}, {"basis", put(b)}}},
        {"mlp_over_full_order", m.median / f.median},
        {"basis_over_full_order", b.median / f.median},
        {"basis_bytes", basis.bases()->bytes()},
        {"command",
         "build/rom_inference --scene " + scene_path + " --threads " + std::to_string(threads)}};
    nsf::write_file_atomic(json, j.dump(2) + "\n");
  }
  return 0;
}
