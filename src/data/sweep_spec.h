#pragma once
// The optional "sweep" section of a scene (docs/SCENES.md, "Sweeps"): which problem parameter μ
// the paper's datasets vary, over which range, how many training and test runs, and how μ enters
// the scene (override templates such as "material.E={mu*1000}"). A sweep may vary more at once
// (issue #55 item 4): further axes ("vary", each in its own value v), and random smooth paths of
// colliders ("paths"), with the runs placed by a Latin hypercube or a Sobol sequence.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "data/collider_path.h"
#include "data/parameter_axis.h"

namespace nsf {

enum class SweepDesign {
  grid,   // μ evenly spaced, test runs at midpoints (one axis only)
  lhs,    // a Latin hypercube over μ and the "vary" axes
  sobol,  // a shifted Sobol sequence over them
};

struct SweepSpec {
  std::string parameter;            // name stored with every run, e.g. "friction_angle"
  std::vector<std::string> set;     // override templates, each "path=value" with {…} expressions
  double lo = 0, hi = 1;            // range of μ, lo < hi
  int train = 2, test = 0;          // run counts
  std::vector<ParameterAxis> vary;  // further axes, applied after μ's templates, in order
  std::vector<ColliderPath> paths;  // random smooth collider paths, applied after the axes
  SweepDesign design = SweepDesign::grid;
  uint64_t seed = 1;  // of the design and the paths
};

// One planned simulation of a sweep.
struct SweepRun {
  std::string split;  // "train" or "test"
  int index = 0;      // position within its split
  double mu = 0;
  std::vector<double> values;  // one per "vary" axis
  uint64_t path_seed = 0;      // of its collider paths
  std::string file() const { return split + "_" + std::to_string(index) + ".h5"; }
};

// Reads and validates the section; `scene` is the whole scene, on which every template is tried
// (with μ = lo) so that a misspelled override path fails at load, not after hours of sweeping.
SweepSpec parse_sweep(const nlohmann::json& sweep, const nlohmann::json& scene);

// A section's "set": override templates "path=value" in `variable` ({mu}, {v}); each must hold
// an expression where `expression_required`. Fails naming `path`.set[i].
std::vector<std::string> parse_templates(const nlohmann::json& section, const std::string& path,
                                         const std::string& variable, bool expression_required);

// A section's "range": [lo, hi] with lo < hi, both numbers; fails naming `path`.range otherwise.
std::pair<double, double> parse_range(const nlohmann::json& section, const std::string& path);

// The grid design: training μ evenly spaced over [lo, hi] including both ends; test μ at
// midpoints of the intervals between neighbouring training values, spread over the range
// (interpolation only). The others: training and test runs from the design over the box of μ and
// the "vary" axes (Latin hypercube: two separate hypercubes; Sobol: the test points follow the
// training ones). Every run has its own path seed.
std::vector<SweepRun> plan_sweep(const SweepSpec& spec);

// Applies one run's overrides to `scene`: μ's templates, the axes' at their values, then the
// collider paths drawn from the run's seed over the scene as the templates left it.
void apply_sweep_run(const SweepSpec& spec, const SweepRun& run, nlohmann::json& scene);

// μ's and the axes' templates with every value at the low (or high) end of its range.
std::vector<std::string> sweep_corner_overrides(const SweepSpec& spec, bool high);

// The run's values by name, μ's first: {"hardening": 0.1, "plate depth": 0.36}.
nlohmann::json sweep_values(const SweepSpec& spec, const SweepRun& run);

// The overrides for one μ: every {expr} of every template replaced by its value. expr is
// f(mu), optionally times a number K, optionally plus or minus a number C (`mu`, `mu*K`,
// `cos_deg(mu)*K+C`, `sin_deg(mu)-C`, …), with f the identity or one of sin_deg, cos_deg, tan_deg
// (argument in degrees).
std::vector<std::string> sweep_overrides(const SweepSpec& spec, double mu);

// The same expansion for templates in another variable (`nsf generalize`'s perturbations use v).
std::vector<std::string> expand_templates(const std::vector<std::string>& templates,
                                          const std::string& variable, double value);

}  // namespace nsf
