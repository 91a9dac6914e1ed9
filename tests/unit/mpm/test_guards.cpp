// The engine's guards (src/mpm/guards.cpp, Simulation::check_time_step): a run that has gone
// wrong stops with an nsf::Error naming the particle (or dt) and what to change.
#include <gtest/gtest.h>

#include "error_matchers.h"

#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"
#include "mpm/scene/scene.h"
#include "mpm/simulation.h"

namespace nsf {
namespace {

// A small elastic block resting in the middle of a 16-cell box.
Scene block_scene(double dt = 1e-4) {
  nlohmann::json j = nlohmann::json::parse(R"({
    "simulation": { "dx": 0.0625, "dt": 1e-4, "ppc": 2 },
    "objects": [{
      "shape": { "type": "box", "min": [0.375, 0.375, 0.375], "max": [0.625, 0.625, 0.625] },
      "material": { "type": "fixed_corotated", "E": 1e4, "nu": 0.3 }
    }]
  })");
  j["simulation"]["dt"] = dt;
  return build_scene(j);
}

using testing::error_of;
using testing::expect_contains;

TEST(Guards, ParticleOutsideTheDomainIsNamedWithTheFix) {
  Scene s = block_scene();
  s.particles.x[17] = Vec3(0.5, -0.2, 0.5);  // pushed through the floor
  std::string msg = error_of([&] { Simulation sim(std::move(s)); });
  expect_contains(msg, "particle 17 left the domain");
  expect_contains(msg, "-0.2");
  expect_contains(msg, "Enlarge simulation.domain_lo/domain_hi");
}

TEST(Guards, ParticleNearTheEdgeOfTheGridIsCaughtAfterAStep) {
  // Inside the grid (its stencil still fits) but within the one-cell margin: the step runs and
  // the check after it names the particle.
  Simulation sim(block_scene());
  sim.particles().x[3] = Vec3(0.5, 0.5, 0.6 * 0.0625);
  std::string msg = error_of([&] { sim.step(); });
  expect_contains(msg, "particle 3 left the domain");
  expect_contains(msg, "step 1");
}

TEST(Guards, NonFiniteStateIsNamedWithTheFix) {
  Simulation sim(block_scene());
  sim.step();
  // A NaN in F spreads no further than its own particle in one step: G2P multiplies F, and the
  // stress (which P2G scatters) is only recomputed after that.
  sim.particles().F[42](1, 1) = std::numeric_limits<double>::quiet_NaN();
  std::string msg = error_of([&] { sim.step(); });
  expect_contains(msg, "simulation blew up");
  expect_contains(msg, "particle 42 has a non-finite");
  expect_contains(msg, "Lower simulation.dt");
}

TEST(Guards, InitialNaNVelocityIsCaughtBeforeTheFirstStep) {
  Scene s = block_scene();
  s.particles.v[5][0] = std::numeric_limits<double>::quiet_NaN();
  std::string msg = error_of([&] { Simulation sim(std::move(s)); });
  expect_contains(msg, "particle 5 has a non-finite");
}

TEST(Guards, SpeedOverTheCflLimitIsNamedWithTheFix) {
  Scene s = block_scene();
  const double vmax = s.settings.cfl * s.settings.dx / s.settings.dt;  // 375 m/s here
  s.particles.v[9] = Vec3(0, 0, 1.5 * vmax);
  std::string msg = error_of([&] { Simulation sim(std::move(s)); });
  expect_contains(msg, "particle 9 moves at");
  expect_contains(msg, "over the CFL limit 375");
  expect_contains(msg, "Lower simulation.dt or the initial velocities");
}

TEST(Guards, TimeStepAboveTheElasticCflBoundIsRejectedAtStart) {
  // E = 1e4, ν = 0.3, ρ = 1000: p-wave speed √(E(1−ν)/((1+ν)(1−2ν))/ρ) ≈ 3.67 m/s, so the
  // bound is 0.6 · 0.0625 / 3.67 ≈ 0.0102 s.
  std::string msg = error_of([] { Simulation sim(block_scene(0.05)); });
  expect_contains(msg, "dt = 0.05 exceeds the CFL bound 0.0102");
  expect_contains(msg, "Lower simulation.dt to at most 0.0102");
  // Just under the bound is accepted.
  EXPECT_NO_THROW(Simulation sim(block_scene(0.0100)));
}

}  // namespace
}  // namespace nsf
