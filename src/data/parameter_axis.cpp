#include "data/parameter_axis.h"

#include <tuple>

#include "core/error.h"
#include "core/json_util.h"
#include "data/sweep_spec.h"
#include "mpm/scene/scene.h"

namespace nsf {

namespace {

// The parts of a scene that decide its particles: the simulation section and each object's shape.
bool same_particles(const nlohmann::json& a, const nlohmann::json& b) {
  const nlohmann::json none;
  if (a.value("simulation", none) != b.value("simulation", none)) return false;
  const nlohmann::json oa = a.value("objects", none), ob = b.value("objects", none);
  if (oa.size() != ob.size()) return false;
  for (size_t i = 0; i < oa.size(); ++i)
    if (oa[i].value("shape", none) != ob[i].value("shape", none)) return false;
  return true;
}

}  // namespace

ParameterAxis parse_parameter_axis(const nlohmann::json& j, const std::string& path,
                                   const nlohmann::json& base,
                                   const std::vector<std::vector<std::string>>& after,
                                   bool change_at_both_ends, const std::string& unchanged_hint) {
  namespace js = nsf::json;
  js::require_object(j, path);
  js::check_keys(j, path, {"name", "range", "set"});
  ParameterAxis p;
  p.name = js::get_string(j, path, "name");
  if (p.name.empty()) fail("scene: '", path, ".name' must not be empty");
  std::tie(p.lo, p.hi) = parse_range(j, path);
  // A template without {v} sets a companion value (the pivot a tilted floor turns about).
  p.set = parse_templates(j, path, "v", false);
  const auto at = [&](const std::vector<std::string>& own, const std::vector<std::string>& then) {
    nlohmann::json s = base;
    apply_overrides(s, own);
    apply_overrides(s, then);
    return s;
  };
  std::vector<size_t> unchanged(after.size(), 0);  // per `after`: the ends that change nothing
  for (double v : {p.lo, p.hi}) {
    std::vector<std::string> overrides;
    try {
      overrides = expand_templates(p.set, "v", v);
      for (const auto& then : after) at(overrides, then);
    } catch (const Error& e) {
      fail("scene: '", path, ".set' does not apply at v = ", v, ": ", e.what());
    }
    if (!same_particles(at(overrides, {}), at({}, {})))
      fail("scene: '", path, "' (\"", p.name,
           "\") changes the particles (an object's shape or the simulation section) at v = ", v,
           ": a reduced model runs on the particles it was trained on; move a collider, set a ",
           "velocity or change a material instead");
    for (size_t k = 0; k < after.size(); ++k)
      if (at(overrides, after[k]) == at({}, after[k]) &&
          (change_at_both_ends || ++unchanged[k] == 2))
        fail("scene: '", path, "' (\"", p.name, "\") leaves the scene unchanged at v = ", v,
             change_at_both_ends ? "" : " and at its other end", unchanged_hint);
  }
  return p;
}

}  // namespace nsf
