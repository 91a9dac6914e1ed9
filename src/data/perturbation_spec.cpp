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
  js::check_keys(j, path, {"perturbations", "draws", "seed", "calibration_seed"});
  GeneralizeSpec s;
  if (!j.contains("perturbations") || !j.at("perturbations").is_array() ||
      j.at("perturbations").empty())
    fail("scene: '", path, ".perturbations' must be a non-empty array, got ",
         j.contains("perturbations") ? j.at("perturbations").dump() : std::string("nothing"));
  // The scene as a draw runs it: the sweep's other axes, the perturbation, then μ's templates;
  // here with the axes at either end and μ at either end.
  nlohmann::json base = scene;
  base.erase("generalize");
  base.erase("sweep");
  std::vector<nlohmann::json> bases = {base};
  std::vector<std::vector<std::string>> after = {{}};
  if (sweep) {
    after = {sweep_overrides(*sweep, sweep->lo), sweep_overrides(*sweep, sweep->hi)};
    if (!sweep->vary.empty()) {
      bases = {base, base};
      for (size_t k = 0; k < sweep->vary.size(); ++k)
        for (int end = 0; end < 2; ++end)
          apply_overrides(bases[size_t(end)],
                          expand_templates(sweep->vary[k].set, "v",
                                           end ? sweep->vary[k].hi : sweep->vary[k].lo));
    }
  }
  const std::string hint =
      std::string(sweep ? " once the sweep's templates are applied (it may set only what the "
                          "sweep sets)"
                        : "") +
      ": a perturbation must change what the training runs hold fixed (a --set of the same key "
      "can make it so; --set generalize=null drops the section)";
  const nlohmann::json& list = j.at("perturbations");
  for (size_t i = 0; i < list.size(); ++i)
    for (const nlohmann::json& b : bases) {
      Perturbation p = parse_parameter_axis(list[i], js::child(js::child(path, "perturbations"), i),
                                            b, after, true, hint);
      if (&b == &bases.front()) s.perturbations.push_back(std::move(p));
    }
  s.draws = js::get_int(j, path, "draws", 10, 1, 10000);
  s.seed = uint64_t(js::get_int(j, path, "seed", 1, 0, 1 << 30));
  s.calibration_seed =
      uint64_t(js::get_int(j, path, "calibration_seed", int(s.seed) + 1000, 0, (1 << 30) + 1000));
  if (s.calibration_seed == s.seed)
    fail("scene: 'generalize.calibration_seed' must differ from 'generalize.seed' (", s.seed,
         "): a model calibrated on the benchmark's own draws would be scored on them");
  return s;
}

std::vector<PerturbationDraw> plan_draws(const GeneralizeSpec& spec, const SweepSpec* sweep,
                                         int count, uint64_t seed) {
  if (spec.perturbations.empty()) fail("generalize: the scene lists no perturbations");
  std::mt19937_64 rng(seed);
  // The axes from a stream of their own, so that a scene's draws keep their v and μ when its
  // sweep gains axes.
  std::mt19937_64 axes_rng(seed ^ 0x9e3779b97f4a7c15ULL);
  std::vector<PerturbationDraw> draws;
  for (int i = 0; i < count; ++i) {
    const Perturbation& p = spec.perturbations[size_t(i) % spec.perturbations.size()];
    PerturbationDraw d;
    d.index = i;
    d.perturbation = p.name;
    d.value = p.lo + (p.hi - p.lo) * unit_draw(rng);
    const double u = unit_draw(rng);  // drawn with or without a sweep, so draws do not shift
    if (sweep) d.mu = sweep->lo + (sweep->hi - sweep->lo) * u;
    // The sweep's other axes, each uniform in its range.
    if (sweep)
      for (const ParameterAxis& a : sweep->vary)
        d.values.push_back(a.lo + (a.hi - a.lo) * unit_draw(axes_rng));
    d.overrides = expand_templates(p.set, "v", d.value);
    draws.push_back(std::move(d));
  }
  return draws;
}

}  // namespace nsf
