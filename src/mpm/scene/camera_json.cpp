#include "mpm/scene/camera_json.h"

#include <utility>

#include "core/error.h"
#include "core/json_util.h"

namespace nsf {

std::optional<SceneCamera> parse_camera(const nlohmann::json& scene) {
  namespace js = nsf::json;
  if (!scene.is_object() || !scene.contains("camera")) return std::nullopt;
  const nlohmann::json& j = scene.at("camera");
  const std::string path = "camera";
  js::require_object(j, path);
  js::check_keys(j, path, {"eye", "target", "up", "fov_deg"});
  SceneCamera cam;
  cam.eye = js::get_vec3(j, path, "eye");
  cam.target = js::get_vec3(j, path, "target");
  cam.up = js::get_vec3(j, path, "up", cam.up);
  // Open at both ends: 0 would be a pinhole with no picture, 180 an infinitely wide one.
  cam.fov_deg = js::get_number(j, path, "fov_deg", cam.fov_deg, {0, 180, true, true});
  // Beyond 1e6 m (as far as nsf render draws a particle, io/position_check.h) the view's
  // directions overflow: a camera at 1e300 m used to be "parallel to the view direction".
  constexpr double kMaxCoordinate = 1e6;
  for (const auto& [key, v] :
       {std::pair{"eye", cam.eye}, std::pair{"target", cam.target}, std::pair{"up", cam.up}})
    if (!(v.cwiseAbs().maxCoeff() <= kMaxCoordinate))
      fail("scene: 'camera.", key, "' = [", v.transpose(),
           "] is out of range: each coordinate must lie within 1e6 m of the origin");
  if (!((cam.target - cam.eye).norm() > 0))
    fail("scene: 'camera.eye' and 'camera.target' must differ");
  if (!(cam.up.norm() > 0)) fail("scene: 'camera.up' must not be zero");
  if (cam.up.normalized().cross((cam.target - cam.eye).normalized()).norm() < 1e-6)
    fail("scene: 'camera.up' = [", cam.up.transpose(), "] is parallel to the view direction");
  return cam;
}

}  // namespace nsf
