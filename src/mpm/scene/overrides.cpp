// Command-line overrides "a.b[2].c=value" (docs/SCENES.md, "Overrides").
#include <algorithm>
#include <cctype>

#include "core/error.h"
#include "core/json_parse.h"
#include "core/json_util.h"
#include "mpm/scene/scene.h"
#include "mpm/scene/scene_keys.h"

namespace nsf {
namespace {

using Json = nlohmann::json;

struct Step {
  bool is_index = false;
  std::string key;
  size_t index = 0;
};

std::string step_path(const std::vector<Step>& steps, size_t count) {
  std::string p;
  for (size_t i = 0; i < count; ++i)
    p = steps[i].is_index ? json::child(p, steps[i].index) : json::child(p, steps[i].key);
  return p;
}

std::vector<Step> parse_path(const std::string& path, const std::string& what) {
  std::vector<Step> steps;
  size_t i = 0;
  auto bad = [&](const char* why) {
    fail("override '", what, "': ", why, " in path '", path, "'");
  };
  while (i < path.size()) {
    size_t end = path.find_first_of(".[", i);
    if (end == std::string::npos) end = path.size();
    if (end == i) bad("empty key");
    steps.push_back({false, path.substr(i, end - i), 0});
    i = end;
    while (i < path.size() && path[i] == '[') {
      size_t close = path.find(']', i);
      if (close == std::string::npos || close == i + 1) bad("malformed [index]");
      std::string digits = path.substr(i + 1, close - i - 1);
      if (!std::all_of(digits.begin(), digits.end(), [](char c) { return std::isdigit(c); }))
        bad("non-numeric [index]");
      // An index past any array is an error at set_at; one past size_t would overflow here.
      if (digits.size() > 18) bad("[index] too large");
      steps.push_back({true, "", static_cast<size_t>(std::stoull(digits))});
      i = close + 1;
    }
    if (i < path.size()) {
      if (path[i] != '.') bad("expected '.' or '['");
      if (++i == path.size()) bad("trailing '.'");
    }
  }
  if (steps.empty()) bad("empty path");
  return steps;
}

// A value that is not valid JSON is taken as a bare string, so "contact=slip" works unquoted.
// `what` names the override in a depth error.
Json parse_value(const std::string& text, const std::string& what) {
  try {
    return json::parse_bounded(text, what);
  } catch (const Json::parse_error&) {
    return text;
  }
}

// Walks to the parent of the last step (which must exist) and sets the value there.
void set_at(Json& root, const std::vector<Step>& steps, const Json& value,
            const std::string& what) {
  Json* node = &root;
  for (size_t s = 0; s < steps.size(); ++s) {
    const Step& st = steps[s];
    const bool last = s + 1 == steps.size();
    const std::string here = step_path(steps, s + 1);
    const std::string parent = s == 0 ? std::string("<root>") : step_path(steps, s);
    if (st.is_index) {
      if (!node->is_array()) fail("override '", what, "': '", parent, "' is not an array");
      if (st.index >= node->size())
        fail("override '", what, "': '", here, "' does not exist ('", parent, "' has ",
             node->size(), " entries)");
      node = &(*node)[st.index];
    } else {
      if (!node->is_object()) fail("override '", what, "': '", parent, "' is not an object");
      // Only the last key may be new (an optional key not yet written); validation then
      // rejects it if it is not a legal key there.
      if (!last && !node->contains(st.key))
        fail("override '", what, "': '", here, "' does not exist in the scene");
      node = &(*node)[st.key];
    }
  }
  *node = value;
}

bool is_object_key(const std::string& k) {
  const auto& keys = object_keys();
  return std::find(keys.begin(), keys.end(), k) != keys.end();
}

bool is_top_level_key(const std::string& k) {
  const auto& keys = top_level_keys();
  return std::find(keys.begin(), keys.end(), k) != keys.end();
}

// "material.E=5" means every object's material: the first key is no top-level key but one every
// object has (or may have).
bool broadcasts_to_objects(const Json& root, const std::string& first) {
  if (root.contains(first) || is_top_level_key(first)) return false;
  auto it = root.find("objects");
  if (it == root.end() || !it->is_array() || it->empty()) return false;
  bool all_have = std::all_of(it->begin(), it->end(),
                              [&](const Json& o) { return o.is_object() && o.contains(first); });
  return all_have || is_object_key(first);
}

}  // namespace

void apply_overrides(Json& scene, const std::vector<std::string>& overrides) {
  for (const std::string& ov : overrides) {
    size_t eq = ov.find('=');
    if (eq == std::string::npos)
      fail("override '", ov, "' must look like path=value, e.g. simulation.dt=1e-4");
    std::vector<Step> steps = parse_path(ov.substr(0, eq), ov);
    Json value = parse_value(ov.substr(eq + 1), "the value of override '" + ov.substr(0, eq) + "'");
    if (steps[0].is_index) fail("override '", ov, "': a path must start with a key");

    if (broadcasts_to_objects(scene, steps[0].key)) {
      Json& objects = scene["objects"];
      for (size_t i = 0; i < objects.size(); ++i) {
        std::vector<Step> full = {{false, "objects", 0}, {true, "", i}};
        full.insert(full.end(), steps.begin(), steps.end());
        set_at(scene, full, value, ov);
      }
      continue;
    }
    if (steps.size() == 1 && !is_top_level_key(steps[0].key))
      fail("override '", ov, "': '", steps[0].key,
           "' is neither a top-level section nor a key of the objects");
    set_at(scene, steps, value, ov);
  }
}

}  // namespace nsf
