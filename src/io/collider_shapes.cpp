#include "io/collider_shapes.h"

#include "core/error.h"
#include "core/json_parse.h"
#include "mpm/colliders/box_collider.h"
#include "mpm/colliders/cylinder_collider.h"
#include "mpm/colliders/plane_collider.h"

namespace nsf {

namespace {

std::string path_of(size_t i) {
  return "colliders[" + std::to_string(i) + "]";
}

ColliderShape shape_of(const Collider& c, const std::string& path) {
  ColliderShape s;
  if (const auto* box = dynamic_cast<const BoxCollider*>(&c)) {
    s.kind = ColliderShape::Kind::Box;
    s.half = box->half_size();
  } else if (const auto* cyl = dynamic_cast<const CylinderCollider*>(&c)) {
    s.kind = ColliderShape::Kind::Cylinder;
    s.radius = cyl->radius();
    s.height = cyl->height();
    s.axis = cyl->axis();
  } else if (dynamic_cast<const PlaneCollider*>(&c)) {
    s.kind = ColliderShape::Kind::Plane;
  } else {
    // A kind added to the collider factory without a picture; better said than silently missing.
    fail("render: ", path, " is a '", c.type(),
         "' collider, which the renderer cannot draw (use --no-colliders)");
  }
  const auto& rigid = static_cast<const RigidCollider&>(c);
  s.center = rigid.pose().center;
  s.rotation = rigid.pose().rotation;
  if (s.kind == ColliderShape::Kind::Plane) s.normal = rigid.normal(s.center);
  return s;
}

}  // namespace

SceneColliders::SceneColliders(nlohmann::json colliders) {
  if (colliders.is_null()) return;
  if (!colliders.is_array())
    fail("render: the scene's 'colliders' must be an array, got ", colliders.dump());
  colliders_ = std::move(colliders);
  at(0.0);  // validates every entry now
}

SceneColliders SceneColliders::from_scene_json(const std::string& scene_json) {
  const nlohmann::json scene =
      json::parse_bounded_or_discarded(scene_json, "the run's stored scene");
  // A run without a readable scene simply has no colliders to show; the rest of the picture
  // does not depend on it either (scene_hints is as forgiving).
  if (scene.is_discarded() || !scene.is_object()) return {};
  auto it = scene.find("colliders");
  if (it == scene.end()) return {};
  try {
    return SceneColliders(*it);
  } catch (const Error& e) {
    fail("cannot draw the run's colliders: ", e.what(), " (--no-colliders leaves them out)");
  }
}

std::vector<ColliderShape> SceneColliders::at(double t) const {
  std::vector<ColliderShape> out;
  for (size_t i = 0; i < colliders_.size(); ++i) {
    const std::unique_ptr<Collider> c = make_collider(colliders_[i], path_of(i));
    c->set_time(t);
    out.push_back(shape_of(*c, path_of(i)));
  }
  return out;
}

bool bounds(const ColliderShape& s, Vec3& lo, Vec3& hi) {
  if (s.kind == ColliderShape::Kind::Plane) return false;
  Vec3 half = s.half;
  if (s.kind == ColliderShape::Kind::Cylinder) {
    half = Vec3::Constant(s.radius);
    half[s.axis] = 0.5 * s.height;
  }
  // The rotated body box's extent along each world axis is Σ_j |R_ij| half_j.
  const Vec3 ext = s.rotation.cwiseAbs() * half;
  lo = s.center - ext;
  hi = s.center + ext;
  return true;
}

}  // namespace nsf
