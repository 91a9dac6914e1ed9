#pragma once
// The optional "sweep" section of a scene (docs/SCENES.md, "Sweeps"): which problem parameter μ
// the paper's datasets vary, over which range, how many training and test runs, and how μ enters
// the scene (override templates such as "material.E={mu*1000}").
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

namespace nsf {

struct SweepSpec {
  std::string parameter;         // name stored with every run, e.g. "friction_angle"
  std::vector<std::string> set;  // override templates, each "path=value" with {…} expressions
  double lo = 0, hi = 1;         // range of μ, lo < hi
  int train = 2, test = 0;       // run counts
};

// One planned simulation of a sweep.
struct SweepRun {
  std::string split;  // "train" or "test"
  int index = 0;      // position within its split
  double mu = 0;
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

// Training μ evenly spaced over [lo, hi] including both ends; test μ at midpoints of the
// intervals between neighbouring training values, spread over the range (interpolation only).
std::vector<SweepRun> plan_sweep(const SweepSpec& spec);

// The overrides for one μ: every {expr} of every template replaced by its value. expr is
// f(mu), optionally times a number K, optionally plus or minus a number C (`mu`, `mu*K`,
// `cos_deg(mu)*K+C`, `sin_deg(mu)-C`, …), with f the identity or one of sin_deg, cos_deg, tan_deg
// (argument in degrees).
std::vector<std::string> sweep_overrides(const SweepSpec& spec, double mu);

// The same expansion for templates in another variable (`nsf generalize`'s perturbations use v).
std::vector<std::string> expand_templates(const std::vector<std::string>& templates,
                                          const std::string& variable, double value);

}  // namespace nsf
