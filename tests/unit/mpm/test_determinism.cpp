// Results must be reproducible: bit-identical for a given scene whatever the thread count,
// because the coloured scatter visits each node's particles in a fixed order.
#include <gtest/gtest.h>
#include <omp.h>

#include "engine_fixtures.h"
#include "mpm/scene/scene.h"
#include "mpm/simulation.h"

namespace nsf {
namespace {

std::vector<Vec3> run_with_threads(int threads) {
  const int saved = omp_get_max_threads();
  omp_set_num_threads(threads);
  Scene s =
      testing::box_scene(Vec3(0.3, 0.11, 0.4), Vec3(0.7, 0.3, 0.6), 1.0 / 32, 2e-4, 1e4, 0.3, 1000);
  for (size_t p = 0; p < s.particles.size(); ++p)
    s.particles.v[p] = Vec3(0.5 * (s.particles.X[p][1] - 0.2), -1.0, 0.2);
  Simulation sim(std::move(s));
  for (int i = 0; i < 100; ++i) sim.step();  // reaches the floor wall: contact included
  omp_set_num_threads(saved);
  return sim.particles().x;
}

TEST(Determinism, BitIdenticalAcrossThreadCounts) {
  const auto a = run_with_threads(1), b = run_with_threads(2), c = run_with_threads(3);
  ASSERT_EQ(a.size(), b.size());
  size_t differ = 0;
  for (size_t p = 0; p < a.size(); ++p) differ += (a[p] != b[p]) + (a[p] != c[p]);
  EXPECT_EQ(differ, 0u);
  EXPECT_NE(a[0], Vec3(0.3 + 1.0 / 128, 0.11 + 1.0 / 128, 0.4 + 1.0 / 128));  // it did move
}

// `nsf rom` builds its scene once: the full-order run hands it back (release_scene) and the
// reduced-order run gets it with its initial particles restored. That must be the scene as built:
// materials hold no state and colliders (moving plates here) take their pose from the time.
TEST(Determinism, ASceneHandedBackWithItsInitialParticlesRunsLikeAFreshOne) {
  const std::string path = std::string(NSF_SOURCE_DIR) + "/scenes/paper/metal_small.json";
  Scene scene = load_scene(path);
  const Particles initial = scene.particles;
  Simulation first(std::move(scene));
  for (int i = 0; i < 30; ++i) first.step();
  Scene back = std::move(first).release_scene();
  back.particles = initial;
  Simulation again(std::move(back)), fresh(load_scene(path));
  for (int i = 0; i < 30; ++i) again.step(), fresh.step();
  EXPECT_EQ(again.particles().x, fresh.particles().x);
  EXPECT_EQ(again.particles().v, fresh.particles().v);
  EXPECT_EQ(again.particles().F, fresh.particles().F);
  EXPECT_EQ(again.particles().tau, fresh.particles().tau);
  EXPECT_NE(again.particles().x, initial.x);  // it did move
}

}  // namespace
}  // namespace nsf
