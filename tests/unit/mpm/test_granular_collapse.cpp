// Validation: collapse of a quasi-2D granular column against the run-out measured in channel
// experiments.
//
// Published laws for the normalised run-out ΔL/L0 = (L∞ − L0)/L0 of a rectangular column of
// height H0 and length L0 released from a back wall in a channel, a = H0/L0:
//   - Lube, Huppert, Sparks & Ray 2005, "Collapses of two-dimensional granular columns",
//     Phys. Rev. E 72, 041301:            ΔL/L0 ≈ 1.2 a        (a ≲ 1.8),
//                                         ΔL/L0 ≈ 1.9 a^(2/3)  (a ≳ 2.8);
//   - Lajeunesse, Monnier & Homsy 2005, "Granular slumping on a horizontal surface",
//     Phys. Fluids 17, 103302: linear ΔL/L0 = λ a for a ≲ 3 and ∝ a^(2/3) above, with a
//     material-dependent λ (glass beads of different sizes and roughness of the bed) up to
//     ≈ 1.6;
//   - (axisymmetric, not used here: Lajeunesse, Mangeney-Castelnau & Vilotte 2004, Phys.
//     Fluids 16, 2371: ΔR/R0 ≈ 1.24 a for a ≲ 1.7.)
// We take a = 1, well inside the linear regime of both studies, so the published band is
// ΔL/L0 ∈ [1.2, 1.6]. The tolerance of ±0.15 added on each side covers (i) the experiments'
// own scatter about their fits (~±10% between materials of similar friction angle) and (ii)
// our resolution: the front is located to one grid cell, dx/L0 = 0.05 here, and the wall
// position to about the same.
//
// Set-up: plane strain, i.e. a slab two particles thick between slip walls in z; the column
// leans on the slip x = domain_lo wall; the floor is a friction plane (rough bed, μ = tan 30°
// ≈ 0.58 like grains glued to the bed; with μ = 10 the result is the same, so the floor is
// effectively no-slip); internal friction angle 30°, typical of the sand and glass beads used in
// the experiments (22°–35°), converted to the engine's Drucker–Prager cone for plane strain
// (plane_strain_dp_angle below: without that conversion the run-out is 0.8).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "mpm/scene/scene.h"
#include "mpm/simulation.h"

namespace nsf {
namespace {

// 24 cells across the column. The run-out converges from below as the grid is refined, because
// the floor's friction acts through the grid nodes over a layer ~1.5 dx thick, which holds back
// the thin front: 16 cells give 1.00, 20 give 1.10, 24 give 1.17, 32 give 1.31 (measured with
// this set-up). 24 is the coarsest inside the band and runs in seconds; see the report in the
// commit message for the investigation.
constexpr double kDx = 0.2 / 24;
constexpr double kWall = 3 * kDx;  // the first 3 node layers of each face are the wall
constexpr double kL0 = 0.2, kH0 = 0.2;
constexpr double kFriction = 30.0;  // Mohr–Coulomb internal friction angle of the grains

// The engine's Drucker–Prager cone (App. F.3, Klár et al. 2016) is fitted to Mohr–Coulomb in
// triaxial compression: √J2 = A·|I1| with A = 2 sin φ / (√3 (3 − sin φ)). In plane strain that
// cone is much stronger than the Mohr–Coulomb material it came from (φ = 30° acts like ≈ 49°).
// The plane-strain match for a non-dilatant return map, as here, is A = sin φ / 3 (e.g. the
// Abaqus theory manual's DP/MC conversion with ψ = 0); this returns the angle to give the
// engine so that its cone has that A.
double plane_strain_dp_angle(double phi_deg) {
  const double A = std::sin(phi_deg * M_PI / 180.0) / 3.0;
  const double s = 3.0 * std::sqrt(3.0) * A / (2.0 + std::sqrt(3.0) * A);
  return std::asin(s) * 180.0 / M_PI;
}

std::string column_scene(double dp_angle) {
  char buf[2048];
  // Domain: 84 × 39 × 7 cells. z spans the minimum 7 cells with the slab in the middle cell.
  std::snprintf(buf, sizeof(buf), R"({
    "simulation": {
      "domain_lo": [0, 0, 0], "domain_hi": [%.17g, %.17g, %.17g],
      "dx": %.17g, "dt": 3e-4, "frames": 1, "substeps": 1, "ppc": 2, "density": 1600,
      "gravity": [0, -9.8, 0], "walls": { "contact": "slip" }
    },
    "objects": [{
      "shape": { "type": "box", "min": [%.17g, %.17g, %.17g], "max": [%.17g, %.17g, %.17g] },
      "material": { "type": "drucker_prager", "E": 2e5, "nu": 0.3, "friction_angle": %.17g }
    }],
    "colliders": [
      { "type": "plane", "point": [0, %.17g, 0], "normal": [0, 1, 0],
        "contact": "friction", "friction": %.17g }
    ]
  })",
                84 * kDx, 39 * kDx, 7 * kDx, kDx, kWall, kWall, kWall, kWall + kL0, kWall + kH0,
                4 * kDx, dp_angle, kWall, std::tan(kFriction * M_PI / 180.0));
  return buf;
}

double kinetic_energy(const Particles& P) {
  double e = 0;
  for (size_t p = 0; p < P.size(); ++p) e += 0.5 * P.mass[p] * P.v[p].squaredNorm();
  return e;
}

// The front: the far edge of the last dx-wide x-bin, in the run of bins starting at the back
// wall, that holds at least kMinCount particles. A grain or two thrown ahead of the deposit
// does not count, but a deposit one particle layer thick (4 particles per bin) does.
double front_position(const Particles& P) {
  constexpr int kMinCount = 2;
  std::vector<int> count(84, 0);
  for (size_t p = 0; p < P.size(); ++p) {
    int b = int(std::floor((P.x[p][0] - kWall) / kDx));
    if (b >= 0 && b < int(count.size())) ++count[b];
  }
  int b = 0;
  while (b < int(count.size()) && count[b] >= kMinCount) ++b;
  return kWall + b * kDx;
}

TEST(GranularCollapse, RunOutOfAnAspectRatioOneColumnMatchesChannelExperiments) {
  Simulation sim(
      build_scene(nlohmann::json::parse(column_scene(plane_strain_dp_angle(kFriction)))));
  const Particles& P = sim.particles();
  double mass = 0;
  for (size_t p = 0; p < P.size(); ++p) mass += P.mass[p];
  // Stopped: kinetic energy below 1e-5 of the column's potential energy M g H0/2, after the
  // collapse had time to start (free fall over H0 takes ~0.2 s); capped at 3 s.
  const double e_stop = 1e-5 * mass * 9.8 * kH0 / 2;
  while (sim.time() < 3.0) {
    for (int i = 0; i < 50; ++i) sim.step();
    if (sim.time() > 0.3 && kinetic_energy(P) < e_stop) break;
  }
  const double front = front_position(P);
  const double runout = (front - kWall - kL0) / kL0;
  EXPECT_LT(kinetic_energy(P), e_stop) << "the flow did not stop within 3 s";
  EXPECT_GE(runout, 1.2 - 0.15);
  EXPECT_LE(runout, 1.6 + 0.15);
}

}  // namespace
}  // namespace nsf
