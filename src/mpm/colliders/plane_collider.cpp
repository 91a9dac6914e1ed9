#include "mpm/colliders/plane_collider.h"

#include "core/error.h"
#include "core/json_util.h"

namespace nsf {

std::unique_ptr<Collider> PlaneCollider::parse(const nlohmann::json& j, const std::string& path) {
  namespace js = nsf::json;
  js::check_keys(j, path, {"type", "point", "normal", "contact", "friction", "motion"});
  Vec3 point = js::get_vec3(j, path, "point");
  Vec3 normal = js::get_vec3(j, path, "normal");
  if (!(normal.norm() > 1e-12))
    fail("scene: '", js::child(path, "normal"), "' = ", j.at("normal").dump(),
         " must be a non-zero vector");
  return std::make_unique<PlaneCollider>(normal, parse_contact(j, path),
                                         RigidMotion::parse(j, path, point, Mat3::Identity()));
}

}  // namespace nsf
