#include "mpm/colliders/cylinder_collider.h"

#include "core/json_util.h"
#include "core/rotation.h"

namespace nsf {

std::unique_ptr<Collider> CylinderCollider::parse(const nlohmann::json& j,
                                                  const std::string& path) {
  namespace js = nsf::json;
  js::check_keys(j, path,
                 {"type", "center", "radius", "height", "axis", "rotate_deg", "contact", "friction",
                  "motion"});
  Vec3 center = js::get_vec3(j, path, "center");
  double radius = js::get_number(j, path, "radius", js::positive());
  double height = js::get_number(j, path, "height", js::positive());
  int axis = axis_index(js::get_string(j, path, "axis", "y"), js::child(path, "axis"));
  Mat3 R = rotation_from_euler_deg(js::get_vec3(j, path, "rotate_deg", Vec3::Zero()));
  return std::make_unique<CylinderCollider>(radius, height, axis, parse_contact(j, path),
                                            RigidMotion::parse(j, path, center, R));
}

}  // namespace nsf
