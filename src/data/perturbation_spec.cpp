#include "data/perturbation_spec.h"

#include <random>
#include <tuple>

#include "core/error.h"
#include "core/json_util.h"
#include "mpm/scene/scene.h"

namespace nsf {

namespace {

// A uniform number in [0, 1) from the generator's raw output: std::mt19937_64's sequence is fixed
// by the standard, the distributions' mapping is not, so the draws are the same with any library.
double unit(std::mt19937_64& rng) {
  return double(rng() >> 11) * 0x1.0p-53;
}

Perturbation parse_perturbation(const nlohmann::json& j, const std::string& path,
                                const nlohmann::json& scene, const SweepSpec* sweep) {
  namespace js = nsf::json;
  js::require_object(j, path);
  js::check_keys(j, path, {"name", "range", "set"});
  Perturbation p;
  p.name = js::get_string(j, path, "name");
  if (p.name.empty()) fail("scene: '", path, ".name' must not be empty");
  std::tie(p.lo, p.hi) = parse_range(j, path);
  // A template without {v} sets a companion value (the pivot a tilted floor turns about).
  p.set = parse_templates(j, path, "v", false);
  nlohmann::json base = scene;
  base.erase("generalize");
  base.erase("sweep");
  // The scene as runs see it at μ (the sweep's templates last), with and without the perturbation.
  const auto at = [&](const std::vector<std::string>& perturbation, double mu) {
    nlohmann::json s = base;
    apply_overrides(s, perturbation);
    if (sweep) apply_overrides(s, sweep_overrides(*sweep, mu));
    return s;
  };
  for (double v : {p.lo, p.hi}) {
    std::vector<std::string> overrides;
    try {
      overrides = expand_templates(p.set, "v", v);
      at(overrides, 0);
    } catch (const Error& e) {
      fail("scene: '", path, ".set' does not apply at v = ", v, ": ", e.what());
    }
    // The reduced model is tied to the particles it was trained on: a perturbation may move
    // colliders, set velocities or change materials, not the bodies' shapes or the sampling.
    const nlohmann::json perturbed = at(overrides, 0), plain = at({}, 0);
    bool same_particles = perturbed.value("simulation", nlohmann::json()) ==
                              plain.value("simulation", nlohmann::json()) &&
                          perturbed.value("objects", nlohmann::json()).size() ==
                              plain.value("objects", nlohmann::json()).size();
    for (size_t i = 0; same_particles && i < plain.value("objects", nlohmann::json()).size(); ++i)
      same_particles = perturbed["objects"][i].value("shape", nlohmann::json()) ==
                       plain["objects"][i].value("shape", nlohmann::json());
    if (!same_particles)
      fail("scene: '", path, "' (\"", p.name,
           "\") changes the particles (an object's shape or the ", "simulation section) at v = ", v,
           ": a reduced model runs on the particles it was trained on; move a collider, set a ",
           "velocity or change a material instead");
    for (double mu : sweep ? std::vector<double>{sweep->lo, sweep->hi} : std::vector<double>{0})
      if (at(overrides, mu) == at({}, mu))
        fail("scene: '", path, "' (\"", p.name, "\") leaves the scene unchanged at v = ", v,
             sweep ? " once the sweep's templates are applied (it may set only what the sweep sets)"
                   : "",
             ": a perturbation must change what the training runs hold fixed (a --set of the "
             "same key can make it so; --set generalize=null drops the section)");
  }
  return p;
}

}  // namespace

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
  const nlohmann::json& list = j.at("perturbations");
  for (size_t i = 0; i < list.size(); ++i)
    s.perturbations.push_back(
        parse_perturbation(list[i], js::child(js::child(path, "perturbations"), i), scene, sweep));
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
    d.value = p.lo + (p.hi - p.lo) * unit(rng);
    const double u = unit(rng);  // drawn with or without a sweep, so draws do not shift
    if (sweep) d.mu = sweep->lo + (sweep->hi - sweep->lo) * u;
    d.overrides = expand_templates(p.set, "v", d.value);
    draws.push_back(std::move(d));
  }
  return draws;
}

}  // namespace nsf
