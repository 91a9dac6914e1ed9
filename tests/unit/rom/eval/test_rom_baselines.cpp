// The baselines beside each reduced-order row (rom/eval/baselines.h): look-up, interpolation in μ
// and the coarse engine, on hand-made runs whose answers are known, and on a small scene.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "error_matchers.h"
#include "io/run_writer.h"
#include "mpm/particles.h"
#include "mpm/simulation.h"
#include "rom/eval/baselines.h"

namespace fs = std::filesystem;
using ::testing::HasSubstr;

namespace {

const std::string kTinyScene =
    (fs::path(NSF_SOURCE_DIR) / "scenes" / "examples" / "rom_tiny.json").string();

nsf::Particles block(int n) {
  nsf::Particles ps;
  for (int i = 0; i < n; ++i)
    ps.add(nsf::Vec3(0.3 + 0.01 * i, 0.4, 0.5 + 0.002 * i * i), nsf::Vec3::Zero(), 1e-3, 1e-6, {},
           0, 0);
  return ps;
}

// A run whose particle p sits at X_p + (μ t, (0.2 + 0.1 p) t, 0): linear in μ and in t, so that
// blending runs in μ and frames in t is exact.
void write_run(const std::string& path, double mu, double frame_dt, int frames, int n = 20) {
  nsf::Particles ps = block(n);
  nsf::SimSettings s;
  s.dx = 0.02;
  s.dt = frame_dt;
  nsf::RunWriter w(path, ps, s, "line", "{}");
  for (int f = 0; f <= frames; ++f) {
    const double t = f * frame_dt;
    for (size_t p = 0; p < ps.size(); ++p)
      ps.x[p] = ps.X[p] + nsf::Vec3(mu * t, (0.2 + 0.1 * double(p)) * t, 0);
    w.write_frame(ps, t);
  }
  w.finish();
}

// δ of eq. (11) of a run at μ_a against the truth at μ, as the formula gives it.
double shift_delta(const std::string& truth_path, double mu, double mu_a, int frames) {
  const nsf::RunReader truth(truth_path);
  double num = 0, den = 0;
  for (int f = 1; f <= frames; ++f) {
    const double t = truth.times()[size_t(f)];
    for (const nsf::Vec3& x : truth.read_positions(size_t(f)))
      num += std::pow((mu_a - mu) * t, 2), den += x.squaredNorm();
  }
  return std::sqrt(num / den);
}

class Baselines : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) / ("nsf_baselines_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

}  // namespace

TEST_F(Baselines, LookUpPlaysTheNearestRunAndInterpolationIsExactForMotionLinearInMu) {
  write_run(path("truth.h5"), 0.8, 0.05, 10);
  write_run(path("a.h5"), 0.0, 0.05, 10);
  write_run(path("b.h5"), 1.0, 0.025, 20);  // frames twice as dense: every truth time is one
  write_run(path("c.h5"), 3.0, 0.1, 5);     // half as dense: odd frames are blended in t
  const nsf::RunReader truth(path("truth.h5"));
  const std::vector<nsf::TrainingRun> runs = {
      {path("c.h5"), 3.0, {}}, {path("a.h5"), 0.0, {}}, {path("b.h5"), 1.0, {}}};

  nsf::Baselines inside;
  nsf::measure_sweep_baselines(runs, 0.8, truth, 10, inside);
  EXPECT_EQ(inside.lookup_mu, 1.0);
  EXPECT_NEAR(inside.lookup_delta, shift_delta(path("truth.h5"), 0.8, 1.0, 10), 1e-12);
  EXPECT_GT(inside.lookup_delta, 1e-3);
  EXPECT_EQ(inside.interp_mu_lo, 0.0);
  EXPECT_EQ(inside.interp_mu_hi, 1.0);
  EXPECT_FALSE(inside.interp_extrapolated);
  EXPECT_LT(inside.interp_delta, 1e-12);

  // Beyond the runs: the two nearest, extrapolated, one of them read between its frames.
  write_run(path("far.h5"), 4.0, 0.05, 10);
  const nsf::RunReader far(path("far.h5"));
  nsf::Baselines outside;
  nsf::measure_sweep_baselines(runs, 4.0, far, 10, outside);
  EXPECT_EQ(outside.lookup_mu, 3.0);
  EXPECT_NEAR(outside.lookup_delta, shift_delta(path("far.h5"), 4.0, 3.0, 10), 1e-12);
  EXPECT_EQ(outside.interp_mu_lo, 1.0);
  EXPECT_EQ(outside.interp_mu_hi, 3.0);
  EXPECT_TRUE(outside.interp_extrapolated);
  EXPECT_LT(outside.interp_delta, 1e-12);
}

// Over a sweep with "vary" axes: the nearest run in the box of μ and the axes (each scaled by its
// range), and the d + 1 nearest blended.
TEST_F(Baselines, OverASweepWithAxesTheNearestRunIsNearestInTheBox) {
  write_run(path("truth.h5"), 0.8, 0.05, 10);
  write_run(path("a.h5"), 0.0, 0.05, 10);
  write_run(path("b.h5"), 1.0, 0.05, 10);
  write_run(path("c.h5"), 0.8, 0.05, 10);
  const nsf::RunReader truth(path("truth.h5"));
  // c has the truth's μ, but its axis lies across the box: b is nearer.
  const std::vector<nsf::TrainingRun> runs = {{path("a.h5"), 0.0, {{"depth", 0.5}}},
                                              {path("b.h5"), 1.0, {{"depth", 0.5}}},
                                              {path("c.h5"), 0.8, {{"depth", 3.0}}}};
  nsf::Baselines b;
  nsf::measure_sweep_baselines(runs, 0.8, truth, 10, b, {{"depth", 0.5}});
  EXPECT_EQ(b.lookup_mu, 1.0);
  EXPECT_NEAR(b.lookup_distance, 0.2, 1e-12);
  EXPECT_NEAR(b.lookup_delta, shift_delta(path("truth.h5"), 0.8, 1.0, 10), 1e-12);
  EXPECT_EQ(b.interp_runs, 3);
  EXPECT_GT(b.interp_delta, 0);
  // Without the axes, μ alone: c.
  nsf::Baselines plain;
  nsf::measure_sweep_baselines(runs, 0.8, truth, 10, plain);
  EXPECT_EQ(plain.lookup_mu, 0.8);
  nsf::testing::expect_error(
      [&] {
        nsf::measure_sweep_baselines(runs, 0.8, truth, 10, b, {{"width", 1.0}});
      },
      {"has no value of axis 'width'"});
}

TEST_F(Baselines, RunsThatCannotStandInForTheTruthAreAClearError) {
  write_run(path("truth.h5"), 0.8, 0.05, 10);
  write_run(path("a.h5"), 0.0, 0.05, 10);
  write_run(path("short.h5"), 1.0, 0.05, 4);
  write_run(path("other.h5"), 1.0, 0.05, 10, 21);
  const nsf::RunReader truth(path("truth.h5"));
  nsf::Baselines b;
  nsf::testing::expect_error(
      [&] {
        nsf::measure_sweep_baselines({{path("a.h5"), 0.0, {}}, {path("short.h5"), 1.0, {}}}, 0.8,
                                     truth, 10, b);
      },
      {"short.h5 spans t = [0, 0.2] s, the ground truth needs t = 0.25 s"});
  nsf::testing::expect_error(
      [&] {
        nsf::measure_sweep_baselines({{path("a.h5"), 0.0, {}}, {path("other.h5"), 1.0, {}}}, 0.8,
                                     truth, 10, b);
      },
      {"other.h5 holds other particles than the ground truth"});
  nsf::testing::expect_error(
      [&] {
        nsf::measure_sweep_baselines({{path("a.h5"), 0.0, {}}}, 0.8, truth, 10, b);
      },
      {"at least two training runs"});
  nsf::testing::expect_error(
      [&] {
        nsf::measure_sweep_baselines({{path("a.h5"), 0.0, {}}, {path("a.h5"), 0.0, {}}}, 0.8, truth,
                                     10, b);
      },
      {"have the same mu"});
}

TEST_F(Baselines, CoarserOverridesScaleDxAndDtWhenTheSubstepsDivide) {
  const nlohmann::json scene = {{"simulation", {{"dx", 0.0625}, {"dt", 0.001}, {"substeps", 30}}}};
  EXPECT_EQ(nsf::coarser_overrides(scene, 2),
            (std::vector<std::string>{"simulation.dx=0.125", "simulation.dt=0.002",
                                      "simulation.substeps=15"}));
  EXPECT_EQ(nsf::coarser_overrides(scene, 1.5),
            (std::vector<std::string>{"simulation.dx=0.09375", "simulation.dt=0.0015",
                                      "simulation.substeps=20"}));
  EXPECT_EQ(nsf::coarser_overrides(scene, 4).size(), 1u);  // 30 / 4: Δt stays
  nsf::testing::expect_error([&] { nsf::coarser_overrides(scene, 1); }, {"factor above 1"});
}

// The engine on the truth's own scene reproduces the truth exactly (every particle carried by
// itself alone); at 1.5× Δx it has fewer particles and a small, nonzero error.
TEST_F(Baselines, CoarseEngineOnTheSameSceneIsExactAndACoarserOneClose) {
  const nsf::SceneFile file = nsf::read_scene_file(kTinyScene);
  {
    nsf::Simulation sim(nsf::build_scene_file(file));
    nsf::RunWriter w(path("truth.h5"), sim.particles(), sim.settings(), "rom_tiny",
                     file.json.dump());
    w.write_frame(sim.particles(), sim.time());
    for (int f = 1; f <= 6; ++f) {
      sim.advance_frame();
      w.write_frame(sim.particles(), sim.time());
    }
    w.finish();
  }
  const nsf::RunReader truth(path("truth.h5"));
  nsf::Baselines same;
  nsf::measure_coarse_baseline(file, file.json, truth, 6, 2, true, same);
  EXPECT_EQ(same.coarse_delta, 0.0);
  EXPECT_EQ(same.coarse_particles, truth.particle_count());
  EXPECT_GT(same.coarse_seconds, 0.0);

  const nsf::SceneFile coarse =
      nsf::read_scene_file(kTinyScene, nsf::coarser_overrides(file.json, 1.5));
  nsf::Baselines c;
  nsf::measure_coarse_baseline(coarse, coarse.json, truth, 6, 2, true, c);
  EXPECT_LT(c.coarse_particles, truth.particle_count() / 2);
  EXPECT_GT(c.coarse_delta, 1e-5);
  EXPECT_LT(c.coarse_delta, 0.05);

  // Frames at other times than the truth's cannot be compared.
  nlohmann::json slow = file.json;
  slow["simulation"]["substeps"] = 20;
  nsf::testing::expect_error(
      [&] { nsf::measure_coarse_baseline(file, slow, truth, 6, 2, true, c); },
      {"it needs the same frame times"});
}
