#include "io/scene_hints.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/json_parse.h"

namespace nsf {

namespace {

using Json = nlohmann::json;

const Json* find(const Json& j, const char* key) {
  if (!j.is_object()) return nullptr;
  auto it = j.find(key);
  return it == j.end() ? nullptr : &*it;
}

std::optional<Vec3> vec3(const Json* j) {
  if (!j || !j->is_array() || j->size() != 3) return std::nullopt;
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    if (!(*j)[i].is_number()) return std::nullopt;
    v[i] = (*j)[i].get<double>();
  }
  return v;
}

double number(const Json* j, double fallback) {
  return j && j->is_number() ? j->get<double>() : fallback;
}

std::string type_of(const Json* j) {
  if (!j) return "";
  if (j->is_string()) return j->get<std::string>();
  const Json* t = find(*j, "type");
  return t && t->is_string() ? t->get<std::string>() : "";
}

// An upward plane collider (the usual floor); the highest one wins.
std::optional<double> plane_floor(const Json& scene) {
  const Json* colliders = find(scene, "colliders");
  if (!colliders || !colliders->is_array()) return std::nullopt;
  std::optional<double> best;
  for (const Json& c : *colliders) {
    if (type_of(&c) != "plane" || find(c, "motion")) continue;  // a moving plane is no floor
    const std::optional<Vec3> n = vec3(find(c, "normal")), p = vec3(find(c, "point"));
    if (!n || !p || !(n->norm() > 0) || n->normalized().y() < 0.999) continue;
    best = std::max(best.value_or(p->y()), p->y());
  }
  return best;
}

}  // namespace

std::string material_display_name(const std::string& type) {
  static const std::pair<const char*, const char*> kNames[] = {
      {"fixed_corotated", "fixed corotated"},
      {"stvk_hencky", "StVK Hencky"},
      {"drucker_prager", "Drucker–Prager"},
      {"von_mises", "von Mises"},
      {"herschel_bulkley", "Herschel–Bulkley"}};
  for (const auto& [key, name] : kNames)
    if (type == key) return name;
  std::string out = type;  // a model registered later: its key, readable
  std::replace(out.begin(), out.end(), '_', ' ');
  return out;
}

SceneHints scene_hints(const std::string& scene_json, double dx) {
  SceneHints h;
  const Json scene = json::parse_bounded_or_discarded(scene_json, "the run's stored scene");
  if (scene.is_discarded()) return h;
  const Json* sim = find(scene, "simulation");
  const double ppc = sim ? number(find(*sim, "ppc"), 2) : 2;
  if (dx > 0 && ppc >= 1) h.particle_radius = 0.5 * dx / ppc;

  h.floor_height = plane_floor(scene);
  if (!h.floor_height && sim && dx > 0) {
    // The engine's bottom wall is its outer 3 node layers (SimSettings::wall_nodes).
    if (const std::optional<Vec3> lo = vec3(find(*sim, "domain_lo"))) {
      h.floor_height = lo->y() + 3 * dx;
    } else {
      h.floor_height = 3 * dx;
    }
  }

  try {
    h.camera = parse_camera(scene);
  } catch (const Error& e) {
    fail("the run's scene: ", e.what());
  }

  // Materials are numbered by first appearance of each type, as the scene builder does. An
  // object is named by its index in "objects" and its material: its shape's type ("difference")
  // is how it was built, not what it is.
  if (const Json* objects = find(scene, "objects"); objects && objects->is_array()) {
    std::vector<std::string> types;
    for (size_t i = 0; i < objects->size(); ++i) {
      const Json& o = (*objects)[i];
      const std::string mat = type_of(find(o, "material"));
      h.object_names.push_back("object " + std::to_string(i) +
                               (mat.empty() ? "" : " (" + material_display_name(mat) + ")"));
      if (!mat.empty() && std::find(types.begin(), types.end(), mat) == types.end()) {
        types.push_back(mat);
        h.material_names.push_back(material_display_name(mat));
      }
    }
  }
  return h;
}

}  // namespace nsf
