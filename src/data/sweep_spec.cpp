#include "data/sweep_spec.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <tuple>
#include <utility>

#include "core/error.h"
#include "core/json_util.h"
#include "data/design.h"
#include "mpm/scene/scene.h"

namespace nsf {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Evaluates one template expression (the text between braces): f(var), then an optional factor
// "*K", then an optional offset "+C" or "-C". The offset places a part relative to a pivot, e.g.
// the handle of a brush turned by mu about its head: centre x = cos(mu)·L + x0.
double evaluate(const std::string& expr, const std::string& var, double value,
                const std::string& tmpl) {
  auto bad = [&](const char* why) {
    fail("template '", tmpl, "': '{", expr, "}' ", why, " (allowed: f(", var, "), f(", var,
         ")*K, f(", var, ")+C, f(", var, ")*K+C with f = ", var,
         ", sin_deg, cos_deg, tan_deg and numbers K, C; C may also be subtracted)");
  };
  const double rad = value * kPi / 180.0;
  // The function heads first: the bare variable is a prefix of none of them.
  const std::pair<std::string, double> heads[] = {{"sin_deg(" + var + ")", std::sin(rad)},
                                                  {"cos_deg(" + var + ")", std::cos(rad)},
                                                  {"tan_deg(" + var + ")", std::tan(rad)},
                                                  {var, value}};
  double v = 0;
  size_t pos = std::string::npos;
  for (const auto& [name, head] : heads) {
    if (expr.compare(0, name.size(), name) == 0) {
      v = head;
      pos = name.size();
      break;
    }
  }
  if (pos == std::string::npos) bad("is not a known expression");
  // strtod reads a signed number and stops at the '+' or '-' of an offset after it.
  const auto number = [&](size_t from, size_t& to) {
    const char* start = expr.c_str() + from;
    char* end = nullptr;
    const double k = std::strtod(start, &end);
    if (end == start || !std::isfinite(k)) bad("has a malformed number");
    to = from + static_cast<size_t>(end - start);
    return k;
  };
  if (pos < expr.size() && expr[pos] == '*') v *= number(pos + 1, pos);
  if (pos < expr.size() && (expr[pos] == '+' || expr[pos] == '-')) {
    const double sign = expr[pos] == '-' ? -1 : 1;
    if (pos + 1 < expr.size() && (expr[pos + 1] == '+' || expr[pos + 1] == '-'))
      bad("has a malformed number");
    v += sign * number(pos + 1, pos);
  }
  if (pos != expr.size()) bad("has unexpected text after the expression");
  return v;
}

std::string expand(const std::string& tmpl, const std::string& var, double value) {
  std::string out;
  size_t i = 0;
  while (i < tmpl.size()) {
    const size_t open = tmpl.find('{', i);
    if (open == std::string::npos) {
      out += tmpl.substr(i);
      break;
    }
    const size_t close = tmpl.find('}', open);
    if (close == std::string::npos) fail("template '", tmpl, "': '{' without '}'");
    out += tmpl.substr(i, open - i);
    // nlohmann prints the shortest text that reads back as the same double.
    out +=
        nlohmann::json(evaluate(tmpl.substr(open + 1, close - open - 1), var, value, tmpl)).dump();
    i = close + 1;
  }
  return out;
}

}  // namespace

SweepSpec parse_sweep(const nlohmann::json& j, const nlohmann::json& scene) {
  namespace js = nsf::json;
  const std::string path = "sweep";
  js::require_object(j, path);
  js::check_keys(j, path,
                 {"parameter", "set", "range", "train", "test", "vary", "paths", "design", "seed"});
  SweepSpec s;
  s.parameter = js::get_string(j, path, "parameter");
  if (s.parameter.empty()) fail("scene: '", path, ".parameter' must not be empty");

  s.set = parse_templates(j, path, "mu", true);

  std::tie(s.lo, s.hi) = parse_range(j, path);
  s.train = js::get_int(j, path, "train", 2, 100000);

  // Try the templates at both ends, on a copy without the sweep (no recursion).
  nlohmann::json base = scene;
  base.erase("sweep");
  base.erase("generalize");
  for (double mu : {s.lo, s.hi}) {
    nlohmann::json probe = base;
    try {
      apply_overrides(probe, sweep_overrides(s, mu));
    } catch (const Error& e) {
      fail("scene: '", path, ".set' does not apply at mu = ", mu, ": ", e.what());
    }
  }

  if (j.contains("vary")) {
    const nlohmann::json& list = j.at("vary");
    if (!list.is_array() || list.empty())
      fail("scene: '", path, ".vary' must be a non-empty array of axes, got ", list.dump());
    if (list.size() + 1 > size_t(kSobolMaxDimensions))
      fail("scene: '", path, ".vary' has ", list.size(), " axes; at most ", kSobolMaxDimensions - 1,
           " besides mu");
    // Each axis is checked as runs apply it: after μ's templates at either end and the earlier
    // axes' (at their low end), so that an axis may set a part of what an earlier one made (a
    // throw's second component after a first axis set the velocity).
    nlohmann::json at_lo = base, at_hi = base;
    apply_overrides(at_lo, sweep_overrides(s, s.lo));
    apply_overrides(at_hi, sweep_overrides(s, s.hi));
    const std::string hint =
        " once mu's and the earlier axes' templates are applied: an axis must change what they "
        "leave as it is";
    for (size_t i = 0; i < list.size(); ++i) {
      const std::string where = js::child(js::child(path, "vary"), i);
      ParameterAxis axis = parse_parameter_axis(list[i], where, at_lo, {{}}, false, hint);
      parse_parameter_axis(list[i], where, at_hi, {{}}, false, hint);
      for (const ParameterAxis& other : s.vary)
        if (other.name == axis.name)
          fail("scene: '", where, ".name' = \"", axis.name, "\" is already an axis");
      if (axis.name == s.parameter)
        fail("scene: '", where, ".name' = \"", s.parameter, "\" is the sweep's parameter");
      // Applied after μ's and the earlier axes' templates, an axis must not undo them.
      const auto overwrites = [&](const nlohmann::json& a, const nlohmann::json& b,
                                  const std::string& what) {
        for (double v : {axis.lo, axis.hi}) {
          nlohmann::json x = a, y = b;
          for (nlohmann::json* j : {&x, &y})
            apply_overrides(*j, expand_templates(axis.set, "v", v));
          if (x == y)
            fail("scene: '", where, "' (\"", axis.name, "\") overwrites what ", what,
                 " sets at v = ", v, ": ", what, " would then change nothing");
        }
      };
      overwrites(at_lo, at_hi, "mu");
      for (const ParameterAxis& earlier : s.vary) {
        nlohmann::json b = at_lo;  // `earlier` moved from its low end to its high end
        apply_overrides(b, expand_templates(earlier.set, "v", earlier.hi));
        overwrites(at_lo, b, "'" + earlier.name + "'");
      }
      for (nlohmann::json* x : {&at_lo, &at_hi})
        apply_overrides(*x, expand_templates(axis.set, "v", axis.lo));
      s.vary.push_back(std::move(axis));
    }
  }
  if (j.contains("paths")) {
    const nlohmann::json& list = j.at("paths");
    if (!list.is_array() || list.empty())
      fail("scene: '", path, ".paths' must be a non-empty array of collider paths, got ",
           list.dump());
    nlohmann::json at_lo = base;
    apply_overrides(at_lo, sweep_corner_overrides(s, false));
    for (size_t i = 0; i < list.size(); ++i)
      s.paths.push_back(
          parse_collider_path(list[i], js::child(js::child(path, "paths"), i), at_lo));
  }

  const std::string design = js::get_string(j, path, "design", s.vary.empty() ? "grid" : "lhs");
  if (design == "grid")
    s.design = SweepDesign::grid;
  else if (design == "lhs")
    s.design = SweepDesign::lhs;
  else if (design == "sobol")
    s.design = SweepDesign::sobol;
  else
    fail("scene: '", path, ".design' = \"", design, "\" is not a design (grid, lhs, sobol)");
  if (s.design == SweepDesign::grid && !s.vary.empty())
    fail("scene: '", path, ".design' = \"grid\" spaces mu alone; a sweep with 'vary' axes ",
         "needs \"lhs\" or \"sobol\"");
  // A grid's test runs each need their own interval between training values.
  s.test = s.design == SweepDesign::grid ? js::get_int(j, path, "test", 0, 0, s.train - 1)
                                         : js::get_int(j, path, "test", 0, 0, 100000);
  s.seed = uint64_t(js::get_int(j, path, "seed", 1, 0, 1 << 30));
  return s;
}

std::vector<std::string> parse_templates(const nlohmann::json& j, const std::string& path,
                                         const std::string& variable, bool expression_required) {
  if (!j.contains("set") || !j.at("set").is_array() || j.at("set").empty())
    fail("scene: '", path, ".set' must be a non-empty array of override templates, got ",
         j.contains("set") ? j.at("set").dump() : std::string("nothing"));
  std::vector<std::string> out;
  for (size_t i = 0; i < j.at("set").size(); ++i) {
    const nlohmann::json& t = j.at("set")[i];
    const std::string where = json::child(json::child(path, "set"), i);
    if (!t.is_string()) fail("scene: '", where, "' must be a string, got ", t.dump());
    const std::string text = t.get<std::string>();
    if (text.find('=') == std::string::npos ||
        (expression_required && text.find('{') == std::string::npos))
      fail("scene: '", where, "' = \"", text, "\" must look like \"path=value\" with {", variable,
           "} in it");
    out.push_back(text);
  }
  return out;
}

std::pair<double, double> parse_range(const nlohmann::json& j, const std::string& path) {
  const nlohmann::json* range = j.contains("range") ? &j.at("range") : nullptr;
  if (!range || !range->is_array() || range->size() != 2 || !(*range)[0].is_number() ||
      !(*range)[1].is_number() || !((*range)[0].get<double>() < (*range)[1].get<double>()))
    fail("scene: '", path, ".range' must be [lo, hi] with lo < hi, got ",
         range ? range->dump() : std::string("nothing"));
  return {(*range)[0].get<double>(), (*range)[1].get<double>()};
}

namespace {

// A seed per run and purpose, from the sweep's: splitmix64 of the parts.
uint64_t mix(uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}
uint64_t run_seed(uint64_t seed, const std::string& split, int index) {
  return mix(mix(seed) ^ mix(split == "train" ? 1 : 2) ^ mix(uint64_t(index) + 3));
}

// Runs of one split from design points u (n × d, in [0, 1)).
void add_runs(const SweepSpec& s, const std::string& split, const std::vector<double>& u, int n,
              std::vector<SweepRun>& runs) {
  const size_t d = 1 + s.vary.size();
  for (int i = 0; i < n; ++i) {
    SweepRun r;
    r.split = split, r.index = i, r.mu = s.lo + (s.hi - s.lo) * u[size_t(i) * d];
    for (size_t k = 0; k < s.vary.size(); ++k)
      r.values.push_back(s.vary[k].lo + (s.vary[k].hi - s.vary[k].lo) * u[size_t(i) * d + k + 1]);
    runs.push_back(std::move(r));
  }
}

}  // namespace

std::vector<SweepRun> plan_sweep(const SweepSpec& s) {
  std::vector<SweepRun> runs;
  const int d = 1 + int(s.vary.size());
  if (s.design == SweepDesign::lhs) {
    add_runs(s, "train", latin_hypercube(s.train, d, s.seed), s.train, runs);
    if (s.test > 0) add_runs(s, "test", latin_hypercube(s.test, d, mix(s.seed)), s.test, runs);
  } else if (s.design == SweepDesign::sobol) {
    add_runs(s, "train", sobol_points(1, s.train, d, s.seed), s.train, runs);
    add_runs(s, "test", sobol_points(1 + s.train, s.test, d, s.seed), s.test, runs);
  } else {
    std::vector<double> train(s.train);
    for (int i = 0; i < s.train; ++i) {
      // The last value is exactly hi, not lo + (n-1)·step with rounding.
      train[i] = i + 1 == s.train ? s.hi : s.lo + (s.hi - s.lo) * i / (s.train - 1);
      runs.push_back({"train", i, train[i], {}, 0});
    }
    const int intervals = s.train - 1;
    for (int k = 0; k < s.test; ++k) {
      // Interval floor((k + ½)·intervals/test): evenly spread, distinct because test ≤ intervals.
      const int j = int((k + 0.5) * intervals / s.test);
      runs.push_back({"test", k, 0.5 * (train[j] + train[j + 1]), {}, 0});
    }
  }
  if (!s.paths.empty())
    for (SweepRun& r : runs) r.path_seed = run_seed(s.seed, r.split, r.index);
  return runs;
}

void apply_sweep_run(const SweepSpec& spec, const SweepRun& run, nlohmann::json& scene) {
  if (run.values.size() != spec.vary.size())
    fail("sweep run ", run.file(), " has ", run.values.size(), " values for ", spec.vary.size(),
         " axes");
  apply_overrides(scene, sweep_overrides(spec, run.mu));
  for (size_t k = 0; k < spec.vary.size(); ++k) {
    if (!std::isfinite(run.values[k]))
      fail("the value of axis '", spec.vary[k].name, "' must be a finite number, got ",
           run.values[k]);
    apply_overrides(scene, expand_templates(spec.vary[k].set, "v", run.values[k]));
  }
  for (size_t k = 0; k < spec.paths.size(); ++k)
    apply_overrides(scene, {collider_path_override(spec.paths[k], scene, mix(run.path_seed + k))});
}

std::vector<std::string> sweep_corner_overrides(const SweepSpec& spec, bool high) {
  std::vector<std::string> out = sweep_overrides(spec, high ? spec.hi : spec.lo);
  for (const ParameterAxis& a : spec.vary)
    for (std::string& o : expand_templates(a.set, "v", high ? a.hi : a.lo))
      out.push_back(std::move(o));
  return out;
}

nlohmann::json sweep_values(const SweepSpec& spec, const SweepRun& run) {
  nlohmann::json j = nlohmann::json::object();
  j[spec.parameter] = run.mu;
  for (size_t k = 0; k < spec.vary.size() && k < run.values.size(); ++k)
    j[spec.vary[k].name] = run.values[k];
  return j;
}

std::vector<std::string> expand_templates(const std::vector<std::string>& templates,
                                          const std::string& variable, double value) {
  std::vector<std::string> out;
  for (const std::string& t : templates) out.push_back(expand(t, variable, value));
  return out;
}

std::vector<std::string> sweep_overrides(const SweepSpec& spec, double mu) {
  // NaN would reach the scene as null ("'objects[0].velocity[0]' must be a number, got null").
  if (!std::isfinite(mu))
    fail("mu must be a finite number (it sets the sweep's parameter '", spec.parameter, "'), got ",
         mu);
  return expand_templates(spec.set, "mu", mu);
}

}  // namespace nsf
