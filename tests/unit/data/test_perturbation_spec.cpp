// The "generalize" section (data/perturbation_spec.h): the draws of the benchmark of unseen
// interactions are reproducible from their seed on any machine, lie in their ranges, and a
// perturbation that would leave the scene as its sweep makes it is refused.
#include <gtest/gtest.h>

#include <random>

#include "core/error.h"
#include "data/perturbation_spec.h"
#include "error_matchers.h"

namespace {

using nlohmann::json;
using nsf::testing::expect_contains;

json scene() {
  return json::parse(R"({
    "name": "bar",
    "simulation": {"domain_lo": [0,0,0], "domain_hi": [1,1,1], "dx": 0.04, "dt": 0.001,
                   "frames": 2, "substeps": 2},
    "objects": [{"shape": {"type": "box", "min": [0.2,0.2,0.4], "max": [0.6,0.3,0.6]},
                 "material": {"type": "fixed_corotated", "E": 2e4, "nu": 0.3},
                 "velocity": [1, -1, 0]}],
    "colliders": [{"type": "plane", "point": [0,0.12,0], "normal": [0,1,0]}],
    "sweep": {"parameter": "speed", "set": ["objects[0].velocity=[{mu},-1,0]"], "range": [0.5, 1.5],
              "train": 4}
  })");
}

json section() {
  return json::parse(R"({"draws": 6, "seed": 3, "perturbations": [
    {"name": "spun", "range": [2, 6], "set": ["objects[0].angular_velocity=[0,0,{v}]"]},
    {"name": "tilted", "range": [5, 15], "set": ["colliders[0].normal=[{sin_deg(v)},{cos_deg(v)},0]"]}
  ]})");
}

nsf::SweepSpec sweep_of(const json& s) {
  return nsf::parse_sweep(s.at("sweep"), s);
}

std::string error_of(const json& gen) {
  const json s = scene();
  const nsf::SweepSpec sweep = sweep_of(s);
  try {
    nsf::parse_generalize(gen, s, &sweep);
  } catch (const nsf::Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted: " << gen.dump();
  return "";
}

TEST(PerturbationSpec, DrawsAreReproducibleFromTheSeedAndLieInTheirRanges) {
  const json s = scene();
  const nsf::SweepSpec sweep = sweep_of(s);
  const nsf::GeneralizeSpec spec = nsf::parse_generalize(section(), s, &sweep);
  EXPECT_EQ(spec.draws, 6);
  EXPECT_EQ(spec.seed, 3u);
  EXPECT_EQ(spec.calibration_seed, 1003u) << "the calibration's draws: seed + 1000 by default";
  json own = section();
  own["calibration_seed"] = 7;
  EXPECT_EQ(nsf::parse_generalize(own, s, &sweep).calibration_seed, 7u);
  own["calibration_seed"] = 3;  // the benchmark's
  nsf::testing::expect_error([&] { nsf::parse_generalize(own, s, &sweep); },
                             {"must differ from 'generalize.seed'"});
  const auto a = nsf::plan_draws(spec, &sweep, spec.draws, spec.seed);
  const auto b = nsf::plan_draws(spec, &sweep, spec.draws, spec.seed);
  const auto c = nsf::plan_draws(spec, &sweep, spec.draws, spec.seed + 1);
  ASSERT_EQ(a.size(), 6u);
  // The generator's raw sequence is fixed by the C++ standard; each draw takes v, then μ, from
  // the top 53 bits of one output each: the same numbers with any compiler and library.
  std::mt19937_64 rng(3);
  for (size_t i = 0; i < a.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(a[i].perturbation, i % 2 ? "tilted" : "spun");  // in turn
    const nsf::Perturbation& p = spec.perturbations[i % 2];
    const double uv = double(rng() >> 11) * 0x1.0p-53, umu = double(rng() >> 11) * 0x1.0p-53;
    EXPECT_EQ(a[i].value, p.lo + (p.hi - p.lo) * uv);
    EXPECT_EQ(a[i].mu, 0.5 + 1.0 * umu);
    EXPECT_GE(a[i].value, p.lo);
    EXPECT_LT(a[i].value, p.hi);
    EXPECT_EQ(a[i].value, b[i].value);
    EXPECT_EQ(a[i].mu, b[i].mu);
    EXPECT_EQ(a[i].overrides, b[i].overrides);
    EXPECT_NE(a[i].value, c[i].value);
  }
  EXPECT_EQ(a[0].overrides, std::vector<std::string>{"objects[0].angular_velocity=[0,0," +
                                                     json(a[0].value).dump() + "]"});
}

TEST(PerturbationSpec, APerturbationTheSweepOverwritesOrThatChangesNothingIsRefused) {
  // The sweep sets the whole velocity after the perturbation: a new throw direction there is lost.
  expect_contains(error_of(json::parse(R"({"perturbations": [{"name": "thrown up", "range": [0, 1],
                      "set": ["objects[0].velocity=[1,{v},0]"]}]})")),
                  "leaves the scene unchanged");
  // The floor's own normal: no perturbation at v = 0.
  expect_contains(error_of(json::parse(R"({"perturbations": [{"name": "flat", "range": [0, 10],
                      "set": ["colliders[0].normal=[{sin_deg(v)},{cos_deg(v)},0]"]}]})")),
                  "at v = 0");
  expect_contains(error_of(json::parse(R"({"perturbations": [{"name": "typo", "range": [1, 2],
                      "set": ["colliders[3].normal=[0,{v},0]"]}]})")),
                  "does not apply at v = 1");
  expect_contains(error_of(json::parse(R"({"perturbations": [{"name": "x", "range": [2, 1],
                      "set": ["objects[0].angular_velocity=[0,0,{v}]"]}]})")),
                  "lo < hi");
  // Moving the body changes the particles the model was trained on.
  expect_contains(error_of(json::parse(R"({"perturbations": [{"name": "moved", "range": [0.1, 0.2],
                      "set": ["objects[0].shape.min=[{v},0.2,0.4]"]}]})")),
                  "changes the particles");
  expect_contains(error_of(json::parse(R"({"perturbations": []})")), "non-empty");
  expect_contains(error_of(json::parse(R"({"perturbations": [{"name": "x", "range": [1, 2],
                      "set": ["objects[0].angular_velocity=[0,0,{w}]"]}]})")),
                  "is not a known expression");
  expect_contains(error_of(json::parse(R"({"draws": 0, "perturbations": [{"name": "x",
                      "range": [1, 2], "set": ["objects[0].angular_velocity=[0,0,{v}]"]}]})")),
                  "draws");
  expect_contains(error_of(json::parse(R"({"perturbation": []})")), "perturbation");
}

}  // namespace
