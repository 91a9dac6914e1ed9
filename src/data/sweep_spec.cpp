#include "data/sweep_spec.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <tuple>
#include <utility>

#include "core/error.h"
#include "core/json_util.h"
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
  js::check_keys(j, path, {"parameter", "set", "range", "train", "test"});
  SweepSpec s;
  s.parameter = js::get_string(j, path, "parameter");
  if (s.parameter.empty()) fail("scene: '", path, ".parameter' must not be empty");

  s.set = parse_templates(j, path, "mu", true);

  std::tie(s.lo, s.hi) = parse_range(j, path);
  s.train = js::get_int(j, path, "train", 2, 100000);
  // Each test value needs its own interval between training values.
  s.test = js::get_int(j, path, "test", 0, 0, s.train - 1);

  // Try the templates at both ends, on a copy without the sweep (no recursion).
  for (double mu : {s.lo, s.hi}) {
    nlohmann::json probe = scene;
    probe.erase("sweep");
    try {
      apply_overrides(probe, sweep_overrides(s, mu));
    } catch (const Error& e) {
      fail("scene: '", path, ".set' does not apply at mu = ", mu, ": ", e.what());
    }
  }
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

std::vector<SweepRun> plan_sweep(const SweepSpec& s) {
  std::vector<SweepRun> runs;
  std::vector<double> train(s.train);
  for (int i = 0; i < s.train; ++i) {
    // The last value is exactly hi, not lo + (n-1)·step with rounding.
    train[i] = i + 1 == s.train ? s.hi : s.lo + (s.hi - s.lo) * i / (s.train - 1);
    runs.push_back({"train", i, train[i]});
  }
  const int intervals = s.train - 1;
  for (int k = 0; k < s.test; ++k) {
    // Interval floor((k + ½)·intervals/test): evenly spread, distinct because test ≤ intervals.
    const int j = int((k + 0.5) * intervals / s.test);
    runs.push_back({"test", k, 0.5 * (train[j] + train[j + 1])});
  }
  return runs;
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
