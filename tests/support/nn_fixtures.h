#pragma once
// A tiny synthetic dataset with a known two-dimensional latent structure, written with RunWriter
// in the layout `nsf sweep` produces: x = X + a(t, μ)·f(X) + b(t)·k(X), τ and C linear in a, b.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "io/run_writer.h"
#include "mpm/particles.h"

namespace nsf::test {

// Two runs' outputs equal to the last bit.
inline bool bit_identical(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

inline Particles synthetic_particles(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.2, 0.8);
  Particles ps;
  for (int p = 0; p < n; ++p)
    ps.add(Vec3(u(rng), u(rng), u(rng)), Vec3::Zero(), 1.0, 1.0, MaterialPoint{}, 0, 0);
  return ps;
}

inline void set_synthetic_frame(Particles& ps, double t, double mu) {
  const double a = 0.1 * mu * std::sin(3.0 * t), b = 0.05 * std::cos(2.0 * t);
  const double da = 0.3 * mu * std::cos(3.0 * t), db = -0.1 * std::sin(2.0 * t);  // d/dt
  for (size_t p = 0; p < ps.size(); ++p) {
    const Vec3& X = ps.X[p];
    ps.x[p] = X + a * Vec3(std::sin(3.0 * X.y()), 0.0, 0.2) + b * Vec3(0.0, X.x() * X.x(), X.z());
    ps.v[p] = da * Vec3(std::sin(3.0 * X.y()), 0.0, 0.2) + db * Vec3(0.0, X.x() * X.x(), X.z());
    Mat3 s;
    s << a, b, 0.0, b, -a * X.y(), 0.3 * a, 0.0, 0.3 * a, b * X.x();
    ps.tau[p] = 1e3 * s;
    ps.C[p] << b, a, 0.0, -a, b * X.z(), 0.1, 0.0, a * X.x(), -b;
  }
}

// Writes <dir>/train_k.h5 and test_k.h5 (attribute mu) and a manifest.json.
inline void write_synthetic_dataset(const std::filesystem::path& dir, int particles,
                                    unsigned seed = 7, int frames = 12,
                                    const std::vector<double>& train_mu = {0.5, 1.0, 1.5, 2.0},
                                    const std::string& scene_json = R"({"name": "synthetic"})") {
  std::filesystem::create_directories(dir);
  const double test_mu[] = {1.25};
  SimSettings s;
  s.dt = 0.05;
  s.substeps = 1;
  auto write = [&](const std::string& name, double mu) {
    Particles ps = synthetic_particles(particles, seed);
    RunWriter w((dir / name).string(), ps, s, "synthetic", scene_json);
    w.set_attribute("mu", mu);
    for (int f = 0; f < frames; ++f) {
      set_synthetic_frame(ps, 0.1 * f, mu);
      w.write_frame(ps, 0.1 * f);
    }
    w.finish();
  };
  std::string train_list;
  for (size_t k = 0; k < train_mu.size(); ++k) {
    const std::string name = "train_" + std::to_string(k) + ".h5";
    write(name, train_mu[k]);
    train_list += (k ? ", \"" : "\"") + name + "\"";
  }
  write("test_0.h5", test_mu[0]);
  std::ofstream(dir / "manifest.json") << R"({"scene": "synthetic", "train": [)" << train_list
                                       << R"(], "test": [{"file": "test_0.h5", "mu": 1.25}]})";
}

}  // namespace nsf::test
