// Physics check: the first longitudinal mode of a free–free elastic bar.
// With ν = 0 there is no lateral coupling and the bar is exactly 1D: wave speed c = sqrt(E/ρ),
// mode shape u(X,t) ∝ cos(πX/L) sin(ωt), ω = πc/L, so the period is T = 2L/c.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "engine_fixtures.h"
#include "mpm/simulation.h"

namespace nsf {
namespace {

TEST(ElasticBar, LongitudinalPeriodMatchesAnalytic) {
  const double dx = 1.0 / 64, E = 1e4, rho = 1000, L = 0.5, V = 0.01;
  const Vec3 lo(0.25, 0.5 - 2 * dx, 0.5 - 2 * dx);
  Scene s = testing::box_scene(lo, lo + Vec3(L, 4 * dx, 4 * dx), dx, 5e-4, E, 0.0, rho);
  s.settings.gravity.setZero();
  std::vector<size_t> left_end;
  for (size_t p = 0; p < s.particles.size(); ++p) {
    const double xi = s.particles.X[p][0] - lo[0];
    s.particles.v[p] = Vec3(V * std::cos(M_PI * xi / L), 0, 0);
    if (xi < dx) left_end.push_back(p);
  }
  const double c = std::sqrt(E / rho), T = 2 * L / c;
  Simulation sim(std::move(s));

  // The left end's velocity goes as cos(ωt): find its zero crossings.
  std::vector<double> crossings;
  double prev = V, prev_t = 0;
  while (sim.time() < 1.6 * T) {
    sim.step();
    double v = 0;
    for (size_t p : left_end) v += sim.particles().v[p][0];
    v /= left_end.size();
    if ((prev > 0) != (v > 0))
      crossings.push_back(prev_t + (sim.time() - prev_t) * prev / (prev - v));
    prev = v, prev_t = sim.time();
  }
  ASSERT_GE(crossings.size(), 3u) << "the bar did not oscillate";
  const double measured = crossings[2] - crossings[0];
  EXPECT_NEAR(measured, T, 0.05 * T);
}

}  // namespace
}  // namespace nsf
