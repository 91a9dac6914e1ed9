// Simulation::transfer_velocity: P2G then G2P with no forces. APIC carries an affine velocity
// field through the grid exactly; anything else comes back smoothed, and that difference is
// what the reduced-order step's FLIP-style correction (RomOptions::flip) gives back.
#include <gtest/gtest.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "engine_fixtures.h"
#include "mpm/colliders/rigid_collider.h"
#include "mpm/simulation.h"

namespace nsf {
namespace {

Scene cube_scene() {
  Scene s =
      testing::box_scene(Vec3(0.4, 0.4, 0.4), Vec3(0.6, 0.6, 0.6), 0.05, 1e-4, 1e4, 0.3, 1000.0);
  // None of these may enter: the round trip has no forces. A sticky floor through the cube's
  // middle would stop the nodes of its lower half.
  s.settings.gravity = Vec3(0, -9.81, 0);
  for (size_t p = 0; p < s.particles.size(); ++p) s.particles.tau[p] = 1e4 * Mat3::Identity();
  s.colliders.push_back(make_collider(
      nlohmann::json::parse(
          R"({"type": "plane", "point": [0, 0.5, 0], "normal": [0, 1, 0], "contact": "sticky"})"),
      "colliders[0]"));
  return s;
}

std::vector<uint32_t> every_third(size_t n) {
  std::vector<uint32_t> ids;
  for (size_t p = 0; p < n; p += 3) ids.push_back(uint32_t(p));
  return ids;
}

TEST(TransferRoundTrip, ReturnsAnAffineVelocityFieldWithItsGradientExactly) {
  Simulation sim(cube_scene());
  Particles& P = sim.particles();
  Mat3 B;
  B << 0.3, -1.2, 0.5, 0.8, 0.1, -0.4, -0.6, 0.9, 0.2;
  const Vec3 a(0.7, -0.2, 0.4);
  for (size_t p = 0; p < P.size(); ++p) P.v[p] = a + B * P.x[p], P.C[p] = B;
  const Particles before = P;
  const std::vector<uint32_t> ids = every_third(P.size());
  std::vector<Vec3> v;
  sim.transfer_velocity(ids, v);
  ASSERT_EQ(v.size(), ids.size());
  double worst = 0;
  for (size_t k = 0; k < ids.size(); ++k) worst = std::max(worst, (v[k] - P.v[ids[k]]).norm());
  EXPECT_LT(worst, 1e-12);
  for (size_t p = 0; p < P.size(); ++p) {  // nothing moved or changed
    EXPECT_EQ(P.x[p], before.x[p]);
    EXPECT_EQ(P.v[p], before.v[p]);
    EXPECT_EQ(P.C[p], before.C[p]);
    EXPECT_EQ(P.F[p], before.F[p]);
  }
}

TEST(TransferRoundTrip, SmoothsAFieldWithoutItsGradient) {
  // The same linear field with C = 0 (PIC): the round trip returns a blurred, different field,
  // so the test above would notice a transfer that ignored the velocities.
  Simulation sim(cube_scene());
  Particles& P = sim.particles();
  for (size_t p = 0; p < P.size(); ++p)
    P.v[p] = Vec3(std::sin(40.0 * P.x[p][1]), 0, 0), P.C[p] = Mat3::Zero();
  const std::vector<uint32_t> ids = every_third(P.size());
  std::vector<Vec3> v;
  sim.transfer_velocity(ids, v);
  double lost = 0, total = 0;
  for (size_t k = 0; k < ids.size(); ++k)
    lost += (v[k] - P.v[ids[k]]).squaredNorm(), total += P.v[ids[k]].squaredNorm();
  EXPECT_GT(lost, 1e-3 * total);
  EXPECT_LT(lost, total);
}

}  // namespace
}  // namespace nsf
