#include "data/scene_family.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.h"

namespace nsf {

namespace {

// What a scene's leaves are taken from: every value that changes what is simulated (the CFL
// factor only bounds the step the engine accepts).
bool simulated(const std::string& at) {
  for (const char* skip : {"/name", "/description", "/camera", "/rom", "/train", "/sweep",
                           "/generalize", "/simulation/cfl"})
    if (at == skip) return false;
  return true;
}

// Calls f(pointer, value) on each leaf of `j` (an empty object or array is a leaf too, so that a
// collider list emptied is seen).
template <class F>
void each_leaf(const nlohmann::json& j, const std::string& at, const F& f) {
  if (j.is_object() && !j.empty()) {
    for (const auto& [key, value] : j.items())
      if (simulated(at + "/" + key)) each_leaf(value, at + "/" + key, f);
  } else if (j.is_array() && !j.empty()) {
    for (size_t i = 0; i < j.size(); ++i) each_leaf(j[i], at + "/" + std::to_string(i), f);
  } else {
    f(at, j);
  }
}

bool finite_number(const nlohmann::json& v) {
  return v.is_number() && std::isfinite(v.get<double>());
}

std::string number_text(double v) {
  char s[40];
  std::snprintf(s, sizeof s, "%.6g", v);
  return s;
}

}  // namespace

SceneFamily SceneFamily::of(const nlohmann::json& scene) {
  SceneFamily f;
  f.runs_ = 1;
  if (!scene.is_object()) return f;
  each_leaf(scene, "", [&](const std::string& at, const nlohmann::json& v) {
    Leaf& leaf = f.leaves_[at];
    leaf.number = finite_number(v);
    if (leaf.number)
      leaf.lo = leaf.hi = v.get<double>();
    else
      leaf.values = {v.dump()};
  });
  return f;
}

size_t SceneFamily::varying() const {
  size_t n = 0;
  for (const auto& [at, leaf] : leaves_)
    if (leaf.number ? leaf.lo < leaf.hi : leaf.values.size() > 1) ++n;
  return n;
}

void SceneFamily::include(const SceneFamily& other) {
  if (other.empty()) return;
  if (empty()) {
    *this = other;
    return;
  }
  for (auto& [at, leaf] : leaves_)
    if (!other.leaves_.count(at)) leaf.every_run = false;
  for (const auto& [at, theirs] : other.leaves_) {
    auto it = leaves_.find(at);
    if (it == leaves_.end()) {
      Leaf l = theirs;
      l.every_run = false;
      leaves_.emplace(at, std::move(l));
      continue;
    }
    Leaf& mine = it->second;
    mine.every_run = mine.every_run && theirs.every_run;
    if (mine.number && theirs.number) {
      mine.lo = std::min(mine.lo, theirs.lo), mine.hi = std::max(mine.hi, theirs.hi);
      continue;
    }
    // A value that is a number in one run and not in another: keep every value as text.
    if (mine.number) mine.values = {nlohmann::json(mine.lo).dump(), nlohmann::json(mine.hi).dump()};
    std::vector<std::string> add = theirs.values;
    if (theirs.number) add = {nlohmann::json(theirs.lo).dump(), nlohmann::json(theirs.hi).dump()};
    mine.number = false;
    mine.values.insert(mine.values.end(), add.begin(), add.end());
    std::sort(mine.values.begin(), mine.values.end());
    mine.values.erase(std::unique(mine.values.begin(), mine.values.end()), mine.values.end());
  }
  runs_ += other.runs_;
}

std::vector<std::string> SceneFamily::outside(const nlohmann::json& scene) const {
  std::vector<std::string> out;
  if (empty() || !scene.is_object()) return out;
  std::map<std::string, bool> seen;
  each_leaf(scene, "", [&](const std::string& at, const nlohmann::json& v) {
    seen[at] = true;
    auto it = leaves_.find(at);
    if (it == leaves_.end()) {
      out.push_back(at + " = " + v.dump() + ", which no training run's scene has");
      return;
    }
    const Leaf& leaf = it->second;
    if (leaf.number && finite_number(v)) {
      const double x = v.get<double>();
      const double tol = 1e-6 * std::max(std::abs(leaf.lo), std::abs(leaf.hi)) + 1e-12;
      if (x < leaf.lo - tol || x > leaf.hi + tol)
        out.push_back(at + " = " + number_text(x) + ", outside [" + number_text(leaf.lo) + ", " +
                      number_text(leaf.hi) + "] (the training runs)");
      return;
    }
    if (!leaf.number && std::binary_search(leaf.values.begin(), leaf.values.end(), v.dump()))
      return;
    std::string had = leaf.number ? "[" + number_text(leaf.lo) + ", " + number_text(leaf.hi) + "]"
                                  : leaf.values.front();
    if (!leaf.number && leaf.values.size() > 1) had += " and others";
    out.push_back(at + " = " + v.dump() + ", not " + had + " (the training runs)");
  });
  for (const auto& [at, leaf] : leaves_)
    if (leaf.every_run && !seen.count(at))
      out.push_back(at + " is missing, which every training run's scene has");
  return out;
}

nlohmann::json SceneFamily::to_json() const {
  nlohmann::json leaves = nlohmann::json::object();
  for (const auto& [at, leaf] : leaves_) {
    nlohmann::json l = leaf.number ? nlohmann::json{{"range", {leaf.lo, leaf.hi}}}
                                   : nlohmann::json{{"values", leaf.values}};
    if (!leaf.every_run) l["every_run"] = false;
    leaves[at] = std::move(l);
  }
  return {{"runs", runs_}, {"values", std::move(leaves)}};
}

SceneFamily SceneFamily::from_json(const nlohmann::json& j, const std::string& where) {
  const auto bad = [&](const std::string& what) {
    fail(where, ": the scene family ", what, ", got ", j.dump().substr(0, 200));
  };
  if (!j.is_object() || !j.contains("runs") || !j.at("runs").is_number_integer() ||
      j.at("runs").get<long>() < 0 || j.at("runs").get<long>() > 100000000 ||
      !j.contains("values") || !j.at("values").is_object())
    bad("must be {\"runs\": count, \"values\": {pointer: ...}}");
  SceneFamily f;
  f.runs_ = j.at("runs").get<int>();
  for (const auto& [at, l] : j.at("values").items()) {
    Leaf leaf;
    if (!l.is_object()) bad("value '" + at + "' must be an object");
    leaf.every_run = l.value("every_run", true);
    if (l.contains("range")) {
      const nlohmann::json& r = l.at("range");
      if (!r.is_array() || r.size() != 2 || !finite_number(r[0]) || !finite_number(r[1]) ||
          !(r[0].get<double>() <= r[1].get<double>()))
        bad("value '" + at + "' must have a \"range\" [lo, hi] of finite numbers");
      leaf.lo = r[0].get<double>(), leaf.hi = r[1].get<double>();
    } else if (l.contains("values") && l.at("values").is_array() && !l.at("values").empty()) {
      leaf.number = false;
      for (const nlohmann::json& v : l.at("values")) {
        if (!v.is_string()) bad("value '" + at + "' must list its values as JSON text");
        leaf.values.push_back(v.get<std::string>());
      }
      std::sort(leaf.values.begin(), leaf.values.end());
    } else {
      bad("value '" + at + "' must have a \"range\" or \"values\"");
    }
    f.leaves_.emplace(at, std::move(leaf));
  }
  return f;
}

}  // namespace nsf
