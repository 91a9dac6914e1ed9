#include "data/training_box.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "mpm/colliders/rigid_collider.h"

namespace nsf {

namespace {

nlohmann::json vec(const Vec3& v) {
  return {v[0], v[1], v[2]};
}

double finite_number(const nlohmann::json& j, const std::string& where, const char* key) {
  if (!j.contains(key) || !j.at(key).is_number() || !std::isfinite(j.at(key).get<double>()))
    fail(where, ": '", key, "' must be a finite number, got ",
         j.contains(key) ? j.at(key).dump() : std::string("nothing"));
  return j.at(key).get<double>();
}

Vec3 finite_vec(const nlohmann::json& j, const std::string& where, const char* key) {
  const nlohmann::json* v = j.contains(key) ? &j.at(key) : nullptr;
  if (!v || !v->is_array() || v->size() != 3)
    fail(where, ": '", key, "' must be three numbers, got ",
         v ? v->dump() : std::string("nothing"));
  Vec3 out;
  for (int i = 0; i < 3; ++i) {
    if (!(*v)[size_t(i)].is_number() || !std::isfinite((*v)[size_t(i)].get<double>()))
      fail(where, ": '", key, "' must be three finite numbers, got ", v->dump());
    out[i] = (*v)[size_t(i)].get<double>();
  }
  return out;
}

}  // namespace

void TrainingBox::include(const TrainingBox& other) {
  for (const ParameterRange& p : other.parameters) {
    auto it = std::find_if(parameters.begin(), parameters.end(),
                           [&](const ParameterRange& q) { return q.name == p.name; });
    if (it == parameters.end()) {
      parameters.push_back(p);
    } else {
      it->lo = std::min(it->lo, p.lo), it->hi = std::max(it->hi, p.hi);
    }
  }
  for (const ColliderEnvelope& c : other.colliders) {
    auto it = std::find_if(colliders.begin(), colliders.end(),
                           [&](const ColliderEnvelope& d) { return d.collider == c.collider; });
    if (it == colliders.end()) {
      colliders.push_back(c);
      continue;
    }
    it->lo = it->lo.cwiseMin(c.lo), it->hi = it->hi.cwiseMax(c.hi);
    it->max_speed = std::max(it->max_speed, c.max_speed);
    it->max_angular_speed = std::max(it->max_angular_speed, c.max_angular_speed);
  }
  scene.include(other.scene);
}

std::vector<std::string> TrainingBox::describe() const {
  std::vector<std::string> out;
  char line[240];
  for (const ParameterRange& p : parameters) {
    std::snprintf(line, sizeof line, "%s in [%.4g, %.4g]", p.name.c_str(), p.lo, p.hi);
    out.push_back(line);
  }
  for (const ColliderEnvelope& e : colliders) {
    std::snprintf(line, sizeof line,
                  "collider %d's centre in [%.4g, %.4g] x [%.4g, %.4g] x [%.4g, %.4g] m, at most "
                  "%.3g m/s",
                  e.collider, e.lo[0], e.hi[0], e.lo[1], e.hi[1], e.lo[2], e.hi[2], e.max_speed);
    out.push_back(line);
  }
  if (!scene.empty()) {
    std::snprintf(line, sizeof line, "the scene's %zu values over %d runs, %zu of them varying",
                  scene.values(), scene.runs(), scene.varying());
    out.push_back(line);
  }
  return out;
}

nlohmann::json TrainingBox::to_json() const {
  nlohmann::json p = nlohmann::json::array(), c = nlohmann::json::array();
  for (const ParameterRange& r : parameters)
    p.push_back({{"name", r.name}, {"range", {r.lo, r.hi}}});
  for (const ColliderEnvelope& e : colliders)
    c.push_back({{"collider", e.collider},
                 {"lo", vec(e.lo)},
                 {"hi", vec(e.hi)},
                 {"max_speed", e.max_speed},
                 {"max_angular_speed", e.max_angular_speed}});
  nlohmann::json j = {{"parameters", p}, {"colliders", c}};
  if (!scene.empty()) j["scene"] = scene.to_json();
  return j;
}

TrainingBox TrainingBox::from_json(const nlohmann::json& j, const std::string& where) {
  if (!j.is_object()) fail(where, ": a training box must be a JSON object, got ", j.dump());
  TrainingBox box;
  for (const char* key : {"parameters", "colliders"})
    if (j.contains(key) && !j.at(key).is_array())
      fail(where, ": '", key, "' must be an array, got ", j.at(key).dump());
  for (const nlohmann::json& p : j.value("parameters", nlohmann::json::array())) {
    const nlohmann::json* range = p.is_object() && p.contains("range") ? &p.at("range") : nullptr;
    if (!p.is_object() || !p.contains("name") || !p.at("name").is_string() || !range ||
        !range->is_array() || range->size() != 2 || !(*range)[0].is_number() ||
        !(*range)[1].is_number() || !((*range)[0].get<double>() <= (*range)[1].get<double>()))
      fail(where, ": a parameter must be {\"name\": text, \"range\": [lo, hi]}, got ", p.dump());
    box.parameters.push_back(
        {p.at("name").get<std::string>(), (*range)[0].get<double>(), (*range)[1].get<double>()});
  }
  for (const nlohmann::json& c : j.value("colliders", nlohmann::json::array())) {
    if (!c.is_object() || !c.contains("collider") || !c.at("collider").is_number_integer() ||
        c.at("collider").get<long>() < 0 || c.at("collider").get<long>() > 1000000)
      fail(where, ": a collider's envelope must name its 'collider' index, got ", c.dump());
    ColliderEnvelope e;
    e.collider = c.at("collider").get<int>();
    e.lo = finite_vec(c, where, "lo");
    e.hi = finite_vec(c, where, "hi");
    e.max_speed = finite_number(c, where, "max_speed");
    e.max_angular_speed = finite_number(c, where, "max_angular_speed");
    if (!(e.lo.array() <= e.hi.array()).all() || e.max_speed < 0 || e.max_angular_speed < 0)
      fail(where, ": collider ", e.collider, "'s envelope has lo above hi or a negative speed");
    box.colliders.push_back(e);
  }
  if (j.contains("scene")) box.scene = SceneFamily::from_json(j.at("scene"), where);
  return box;
}

std::string TrainingBox::collider_outside(size_t i, const Vec3& center, double speed,
                                          double tolerance) const {
  auto it = std::find_if(colliders.begin(), colliders.end(),
                         [&](const ColliderEnvelope& e) { return size_t(e.collider) == i; });
  if (it == colliders.end()) return "";
  char line[240];
  static const char* axes[] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    const double beyond = std::max(it->lo[a] - center[a], center[a] - it->hi[a]);
    if (beyond > tolerance) {
      std::snprintf(line, sizeof line,
                    "collider %zu's centre is %.3g m beyond its training box in %s (its training "
                    "runs kept it in [%.4g, %.4g] m)",
                    i, beyond, axes[a], it->lo[a], it->hi[a]);
      return line;
    }
  }
  if (speed > 1.1 * it->max_speed + 1e-3) {
    std::snprintf(line, sizeof line,
                  "collider %zu moves at %.3g m/s, faster than its training runs (at most %.3g "
                  "m/s)",
                  i, speed, it->max_speed);
    return line;
  }
  return "";
}

void ColliderEnvelopeRecorder::record(const std::vector<std::unique_ptr<Collider>>& colliders) {
  for (size_t i = 0; i < colliders.size(); ++i) {
    const auto* rigid = dynamic_cast<const RigidCollider*>(colliders[i].get());
    if (!rigid) continue;
    const RigidPose& p = rigid->pose();
    auto it = std::find_if(box_.colliders.begin(), box_.colliders.end(),
                           [&](const ColliderEnvelope& e) { return size_t(e.collider) == i; });
    if (it == box_.colliders.end()) {
      box_.colliders.push_back({int(i), p.center, p.center, 0, 0});
      it = box_.colliders.end() - 1;
    }
    it->lo = it->lo.cwiseMin(p.center), it->hi = it->hi.cwiseMax(p.center);
    it->max_speed = std::max(it->max_speed, p.velocity.norm());
    it->max_angular_speed = std::max(it->max_angular_speed, p.angular_velocity.norm());
  }
}

}  // namespace nsf
