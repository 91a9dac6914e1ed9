#include "data/perturbation_spec.h"

#include <random>

#include "core/error.h"
#include "core/json_util.h"
#include "data/design.h"
#include "mpm/scene/scene.h"

namespace nsf {

GeneralizeSpec parse_generalize(const nlohmann::json& j, const nlohmann::json& scene,
                                const SweepSpec* sweep) {
  namespace js = nsf::json;
  const std::string path = "generalize";
  js::require_object(j, path);
  js::check_keys(j, path, {"perturbations", "draws", "seed"});
  GeneralizeSpec s;
  if (!j.contains("perturbations") || !j.at("perturbations").is_array() ||
      j.at("perturbations").empty())
    fail("scene: '", path, ".perturbations' must be a non-empty array, got ",
         j.contains("perturbations") ? j.at("perturbations").dump() : std::string("nothing"));
  // The scene as runs see it: the perturbation first, then the sweep's templates, here at either
  // end of every axis.
  nlohmann::json base = scene;
  base.erase("generalize");
  base.erase("sweep");
  std::vector<std::vector<std::string>> after = {{}};
  if (sweep) after = {sweep_corner_overrides(*sweep, false), sweep_corner_overrides(*sweep, true)};
  const std::string hint =
      std::string(sweep ? " once the sweep's templates are applied (it may set only what the "
                          "sweep sets)"
                        : "") +
      ": a perturbation must change what the training runs hold fixed (a --set of the same key "
      "can make it so; --set generalize=null drops the section)";
  const nlohmann::json& list = j.at("perturbations");
  for (size_t i = 0; i < list.size(); ++i)
    s.perturbations.push_back(parse_parameter_axis(
        list[i], js::child(js::child(path, "perturbations"), i), base, after, hint));
  s.draws = js::get_int(j, path, "draws", 10, 1, 10000);
  s.seed = uint64_t(js::get_int(j, path, "seed", 1, 0, 1 << 30));
  return s;
}

std::vector<PerturbationDraw> plan_draws(const GeneralizeSpec& spec, const SweepSpec* sweep,
                                         int count, uint64_t seed) {
  if (spec.perturbations.empty()) fail("generalize: the scene lists no perturbations");
  std::mt19937_64 rng(seed);
  std::vector<PerturbationDraw> draws;
  for (int i = 0; i < count; ++i) {
    const Perturbation& p = spec.perturbations[size_t(i) % spec.perturbations.size()];
    PerturbationDraw d;
    d.index = i;
    d.perturbation = p.name;
    d.value = p.lo + (p.hi - p.lo) * unit_draw(rng);
    const double u = unit_draw(rng);  // drawn with or without a sweep, so draws do not shift
    if (sweep) d.mu = sweep->lo + (sweep->hi - sweep->lo) * u;
    // The other axes after, so that a sweep without them keeps its draws.
    if (sweep)
      for (const ParameterAxis& a : sweep->vary)
        d.values.push_back(a.lo + (a.hi - a.lo) * unit_draw(rng));
    d.overrides = expand_templates(p.set, "v", d.value);
    draws.push_back(std::move(d));
  }
  return draws;
}

}  // namespace nsf
