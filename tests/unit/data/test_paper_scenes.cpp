// The paper's seven scenes (scenes/paper/, docs/DATASETS.md): they load, match Table 1's size,
// declare App. A's splits (the jelly more), and a few steps of each small scene run at both ends of
// its range.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "data/sweep_spec.h"
#include "mpm/scene/scene.h"
#include "mpm/simulation.h"

namespace fs = std::filesystem;

namespace {

struct PaperScene {
  const char* name;
  size_t table1_particles;  // Table 1 of the paper
  int train, test;          // App. A, except the jelly and the squishy ball (below)
};

// The jelly sweeps 24/2 runs where App. A has 3/1: with 3 training runs the encoder did not
// generalise to the held-out speed (test δ 3.5 % against 1.5 % on training runs), with 12 it
// over-fitted at long training (1.70 % against 0.73 %), 24 halve that gap (docs/TRAINING.md).
// The squishy ball sweeps 12/2 for the same reason (small scene with 3 runs: ROM δ 23.8 %, the
// ball flattened; 12 runs: 9.3 %). Both sizes sweep the same runs.

const std::vector<PaperScene> kScenes = {{"bread", 40000, 20, 4},       {"cake", 200000, 12, 3},
                                         {"sand", 71363, 16, 4},        {"metal", 49978, 12, 4},
                                         {"toothpaste", 21811, 12, 4},  {"jelly", 10000, 24, 2},
                                         {"squishy_ball", 97857, 12, 2}};

std::string scene_path(const PaperScene& s, const char* size) {
  return (fs::path(NSF_SOURCE_DIR) / "scenes" / "paper" /
          (std::string(s.name) + "_" + size + ".json"))
      .string();
}

nsf::SweepSpec sweep_of(const nsf::Scene& scene) {
  return nsf::parse_sweep(scene.source.at("sweep"), scene.source);
}

TEST(PaperScenes, SmallScenesAreSmallAndDeclareTheirSplits) {
  for (const PaperScene& s : kScenes) {
    SCOPED_TRACE(s.name);
    const nsf::Scene scene = nsf::load_scene(scene_path(s, "small"));
    EXPECT_GE(scene.particles.size(), 2000u);
    EXPECT_LE(scene.particles.size(), 12000u);
    EXPECT_LE(scene.settings.frames, 40);
    const nsf::SweepSpec spec = sweep_of(scene);
    EXPECT_EQ(spec.train, s.train);
    EXPECT_EQ(spec.test, s.test);
  }
}

TEST(PaperScenes, PaperSizesMatchTable1WithinThirtyPercent) {
  for (const PaperScene& s : kScenes) {
    SCOPED_TRACE(s.name);
    const nsf::Scene paper = nsf::load_scene(scene_path(s, "paper"));
    const double n = double(paper.particles.size()), want = double(s.table1_particles);
    EXPECT_NEAR(n / want, 1.0, 0.3) << n << " particles";
    // Both sizes sweep the same thing.
    const nsf::SweepSpec a = sweep_of(paper);
    const nsf::SweepSpec b = sweep_of(nsf::load_scene(scene_path(s, "small")));
    EXPECT_EQ(a.parameter, b.parameter);
    EXPECT_EQ(a.set, b.set);
    EXPECT_EQ(a.lo, b.lo);
    EXPECT_EQ(a.hi, b.hi);
    EXPECT_EQ(a.train, b.train);
    EXPECT_EQ(a.test, b.test);
  }
}

TEST(PaperScenes, TestValuesInterpolateTrainingValues) {
  for (const PaperScene& s : kScenes) {
    SCOPED_TRACE(s.name);
    const nsf::SweepSpec spec = sweep_of(nsf::load_scene(scene_path(s, "small")));
    std::vector<double> train;
    for (const nsf::SweepRun& r : nsf::plan_sweep(spec))
      if (r.split == "train") train.push_back(r.mu);
    for (const nsf::SweepRun& r : nsf::plan_sweep(spec)) {
      if (r.split != "test") continue;
      EXPECT_GT(r.mu, spec.lo);
      EXPECT_LT(r.mu, spec.hi);
      for (double t : train) EXPECT_NE(r.mu, t);
    }
  }
}

// The ends of the range are the hardest cases (stiffest E, steepest angle, fastest throw): they
// must pass the CFL check and survive the first steps without a guard firing.
TEST(PaperScenes, SmallScenesStepAtBothEndsOfTheirRange) {
  for (const PaperScene& s : kScenes) {
    const nlohmann::json base = nsf::read_scene_json(scene_path(s, "small"));
    const nsf::SweepSpec spec = nsf::parse_sweep(base.at("sweep"), base);
    for (double mu : {spec.lo, spec.hi}) {
      SCOPED_TRACE(std::string(s.name) + " at mu = " + std::to_string(mu));
      nlohmann::json j = base;
      nsf::apply_overrides(j, nsf::sweep_overrides(spec, mu));
      nsf::Simulation sim(nsf::build_scene(j));
      EXPECT_NO_THROW(for (int i = 0; i < 3; ++i) sim.step());
    }
  }
}

}  // namespace
