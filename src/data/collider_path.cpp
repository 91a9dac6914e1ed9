#include "data/collider_path.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "core/error.h"
#include "core/json_util.h"
#include "core/rotation.h"
#include "data/design.h"
#include "mpm/colliders/rigid_collider.h"
#include "mpm/scene/settings_json.h"

namespace nsf {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The collider's scripted poses at every frame time 0 … frames.
struct Script {
  std::vector<double> t;
  std::vector<Vec3> center;
  std::vector<Mat3> rotation;
};

Script script_of(const ColliderPath& p, const nlohmann::json& scene, const std::string& where) {
  const nlohmann::json& list = scene.at("colliders");
  const std::string cpath = json::child("colliders", size_t(p.collider));
  std::unique_ptr<Collider> c = make_collider(list.at(size_t(p.collider)), cpath);
  auto* rigid = dynamic_cast<RigidCollider*>(c.get());
  if (!rigid)
    fail("scene: '", where, ".collider' = ", p.collider, " is a ", c->type(),
         " collider, which has no path; a path moves a box, cylinder or plane");
  const SimSettings s = parse_settings(scene.at("simulation"));
  const double frame_dt = s.dt * s.substeps;
  Script out;
  for (int f = 0; f <= s.frames; ++f) {
    const double t = f * frame_dt;
    rigid->set_time(t);
    out.t.push_back(t);
    out.center.push_back(rigid->pose().center);
    out.rotation.push_back(rigid->pose().rotation);
  }
  return out;
}

double fastest(const Script& s, const std::vector<Vec3>& offset, double scale) {
  double v = 0;
  for (size_t f = 1; f < s.t.size(); ++f)
    v = std::max(
        v, ((s.center[f] + scale * offset[f]) - (s.center[f - 1] + scale * offset[f - 1])).norm() /
               (s.t[f] - s.t[f - 1]));
  return v;
}

}  // namespace

ColliderPath parse_collider_path(const nlohmann::json& j, const std::string& path,
                                 const nlohmann::json& scene) {
  namespace js = nsf::json;
  js::require_object(j, path);
  js::check_keys(j, path, {"name", "collider", "start", "end", "offset", "max_speed"});
  ColliderPath p;
  p.name = js::get_string(j, path, "name");
  if (p.name.empty()) fail("scene: '", path, ".name' must not be empty");
  const size_t colliders =
      scene.contains("colliders") && scene["colliders"].is_array() ? scene["colliders"].size() : 0;
  if (colliders == 0) fail("scene: '", path, "' moves a collider, and the scene has none");
  p.collider = js::get_int(j, path, "collider", 0, int(colliders) - 1);
  p.start = js::get_number(j, path, "start", js::non_negative());
  p.end = js::get_number(j, path, "end", js::positive());
  const SimSettings s = parse_settings(scene.at("simulation"));
  const double duration = s.frames * s.dt * s.substeps;
  if (!(p.start < p.end) || p.end > duration * (1 + 1e-12))
    fail("scene: '", path, "' must have start < end ≤ the scene's end (", duration,
         " s), got start = ", p.start, ", end = ", p.end);
  p.offset = js::get_vec3(j, path, "offset");
  if (!(p.offset.minCoeff() >= 0) || !(p.offset.maxCoeff() > 0) || !p.offset.allFinite())
    fail("scene: '", path, ".offset' must be three finite numbers ≥ 0, not all 0 (m), got ",
         j.at("offset").dump());
  p.max_speed = js::get_number(j, path, "max_speed", js::positive());
  collider_path_override(p, scene, 0);  // the script must leave room under max_speed
  return p;
}

std::string collider_path_override(const ColliderPath& p, const nlohmann::json& scene,
                                   uint64_t seed) {
  const std::string where = "sweep path '" + p.name + "'";
  const Script script = script_of(p, scene, where);
  std::mt19937_64 rng(seed);
  Vec3 c[3];
  for (Vec3& ck : c)
    for (int i = 0; i < 3; ++i) ck[i] = p.offset[i] > 0 ? 2 * unit_draw(rng) - 1 : 0.0;
  const double amplitude = 0.5 + 0.5 * unit_draw(rng);
  std::vector<Vec3> offset(script.t.size(), Vec3::Zero());
  double reach = 0;  // the largest excursion over offset, along any axis
  for (size_t f = 0; f < script.t.size(); ++f) {
    const double s = (script.t[f] - p.start) / (p.end - p.start);
    if (s <= 0 || s >= 1) continue;
    for (int k = 0; k < 3; ++k) offset[f] += c[k] * (std::sin((k + 1) * kPi * s) / (k + 1));
    for (int i = 0; i < 3; ++i)
      if (p.offset[i] > 0) reach = std::max(reach, std::abs(offset[f][i]) / p.offset[i]);
  }
  double scale = reach > 0 ? amplitude / reach : 0;
  if (fastest(script, offset, 0) > p.max_speed)
    fail(where, ": the collider's script alone moves at up to ", fastest(script, offset, 0),
         " m/s, faster than max_speed = ", p.max_speed, " m/s");
  for (int i = 0; i < 200 && fastest(script, offset, scale) > p.max_speed; ++i) scale *= 0.9;
  nlohmann::json keys = nlohmann::json::array();
  for (size_t f = 0; f < script.t.size(); ++f) {
    const Vec3 x = script.center[f] + scale * offset[f];
    const Vec3 r = euler_deg_from_rotation(script.rotation[f]);
    keys.push_back(
        {{"t", script.t[f]}, {"center", {x[0], x[1], x[2]}}, {"rotate_deg", {r[0], r[1], r[2]}}});
  }
  return json::child("colliders", size_t(p.collider)) +
         ".motion=" + nlohmann::json{{"keyframes", keys}}.dump();
}

}  // namespace nsf
