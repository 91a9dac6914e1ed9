#pragma once
// One more thing a family of runs varies besides μ, in its own value v: a sweep's "vary" axes
// (docs/SCENES.md, "Sweeps") and `nsf generalize`'s perturbations (docs/GENERALIZE.md) have the
// same form:
//   {"name": "plates squeeze deeper", "range": [0.355, 0.38],
//    "set": ["colliders[1].motion.keyframes[1].center=[{v},0.3,0.5]", ...]}
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace nsf {

struct ParameterAxis {
  std::string name;              // what it does, for tables: "plates squeeze deeper"
  double lo = 0, hi = 0;         // range of v, lo < hi
  std::vector<std::string> set;  // override templates with {v} expressions
};

// Reads and checks an axis at `path` of a scene whose other sections are `base` (without the
// sections that hold axes). Its templates are applied at both ends of its range, followed by each
// list of `after` (the overrides the runs apply after the axis's, e.g. a sweep's at either end of
// μ). At each end the axis must keep the particles (a reduced model runs on the particles it was
// trained on). It must change the scene under every `after`: at both ends with
// `change_at_both_ends` (a perturbation, which perturbs at every value), else at one end at least
// (a sweep's axis may start from the scene's own value: a throw from rest); `unchanged_hint` ends
// the message of that check.
ParameterAxis parse_parameter_axis(const nlohmann::json& j, const std::string& path,
                                   const nlohmann::json& base,
                                   const std::vector<std::vector<std::string>>& after,
                                   bool change_at_both_ends, const std::string& unchanged_hint);

}  // namespace nsf
