#include "mpm/colliders/box_collider.h"

#include "core/json_util.h"
#include "core/rotation.h"

namespace nsf {

std::unique_ptr<Collider> BoxCollider::parse(const nlohmann::json& j, const std::string& path) {
  namespace js = nsf::json;
  js::check_keys(j, path,
                 {"type", "center", "size", "rotate_deg", "contact", "friction", "motion"});
  Vec3 center = js::get_vec3(j, path, "center");
  Vec3 size = js::get_vec3(j, path, "size");
  for (int a = 0; a < 3; ++a)
    js::check_range(size[a], js::child(js::child(path, "size"), static_cast<size_t>(a)),
                    js::positive());
  Mat3 R = rotation_from_euler_deg(js::get_vec3(j, path, "rotate_deg", Vec3::Zero()));
  return std::make_unique<BoxCollider>(size, parse_contact(j, path),
                                       RigidMotion::parse(j, path, center, R));
}

}  // namespace nsf
