// Conservation laws the engine claims: mass, linear momentum and, with APIC, angular momentum.
#include <gtest/gtest.h>

#include "engine_fixtures.h"
#include "mpm/simulation.h"

namespace nsf {
namespace {

using testing::box_scene;

TEST(Conservation, GridReceivesAllMassAndMomentum) {
  Scene s = box_scene(Vec3(0.4, 0.4, 0.4), Vec3(0.6, 0.5, 0.55), 1.0 / 32, 1e-4, 1e4, 0.3, 1000);
  s.settings.gravity.setZero();
  for (size_t p = 0; p < s.particles.size(); ++p) s.particles.v[p] = Vec3(0.3, -0.1, 0.2);
  const double M = testing::total_mass(s.particles);
  Simulation sim(std::move(s));
  sim.step();
  double grid_mass = 0;
  for (size_t i = 0; i < sim.grid().node_count(); ++i) grid_mass += sim.grid()[i].m;
  EXPECT_NEAR(grid_mass, M, 1e-12 * M);
  EXPECT_NEAR(testing::total_mass(sim.particles()), M, 0.0);
}

TEST(Conservation, LinearMomentumInFreeFlight) {
  Scene s = box_scene(Vec3(0.4, 0.4, 0.4), Vec3(0.6, 0.5, 0.55), 1.0 / 32, 1e-4, 1e4, 0.3, 1000);
  s.settings.gravity = Vec3(0, -9.8, 0);
  // A non-uniform initial velocity makes the body deform, so internal forces are exercised.
  for (size_t p = 0; p < s.particles.size(); ++p) {
    const Vec3& X = s.particles.X[p];
    s.particles.v[p] = Vec3(0.2 + 0.5 * (X[1] - 0.45), -0.1, 0.3 * (X[0] - 0.5));
  }
  const double M = testing::total_mass(s.particles);
  const Vec3 P0 = testing::linear_momentum(s.particles);
  Simulation sim(std::move(s));
  const int steps = 200;
  for (int i = 0; i < steps; ++i) sim.step();
  const Vec3 expected = P0 + M * sim.settings().gravity * (steps * sim.settings().dt);
  const Vec3 P1 = testing::linear_momentum(sim.particles());
  EXPECT_LT((P1 - expected).norm(), 1e-10 * expected.norm())
      << P1.transpose() << " vs " << expected.transpose();
}

// Spins an elastic box about a tilted axis with no gravity and no walls in reach.
Vec3 spin_and_measure(Transfer transfer, Vec3* L0_out) {
  const double dx = 1.0 / 32;
  Scene s = box_scene(Vec3(0.4, 0.42, 0.44), Vec3(0.6, 0.58, 0.56), dx, 2e-4, 2e4, 0.3, 1000);
  s.settings.gravity.setZero();
  s.settings.transfer = transfer;
  const Vec3 c(0.5, 0.5, 0.5), omega(0.5, 3.0, 1.0);
  for (size_t p = 0; p < s.particles.size(); ++p) {
    s.particles.v[p] = omega.cross(s.particles.X[p] - c);
    s.particles.C[p] << 0, -omega[2], omega[1], omega[2], 0, -omega[0], -omega[1], omega[0], 0;
  }
  *L0_out = testing::angular_momentum(s.particles, dx, transfer == Transfer::APIC);
  Simulation sim(std::move(s));
  for (int i = 0; i < 500; ++i) sim.step();
  return testing::angular_momentum(sim.particles(), dx, transfer == Transfer::APIC);
}

TEST(Conservation, AngularMomentumWithAPIC) {
  Vec3 L0;
  const Vec3 L1 = spin_and_measure(Transfer::APIC, &L0);
  EXPECT_LT((L1 - L0).norm(), 1e-6 * L0.norm()) << L0.transpose() << " -> " << L1.transpose();
}

TEST(Conservation, AngularMomentumDecaysWithPIC) {
  Vec3 L0;
  const Vec3 L1 = spin_and_measure(Transfer::PIC, &L0);
  // PIC drops the affine part at every transfer, so rotation is visibly damped.
  EXPECT_LT(L1.norm(), 0.9 * L0.norm()) << L0.transpose() << " -> " << L1.transpose();
}

}  // namespace
}  // namespace nsf
