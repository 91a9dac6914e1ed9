#include <functional>
#include <map>

#include "core/error.h"
#include "core/json_util.h"
#include "mpm/colliders/box_collider.h"
#include "mpm/colliders/collider.h"
#include "mpm/colliders/cylinder_collider.h"
#include "mpm/colliders/plane_collider.h"

namespace nsf {

std::unique_ptr<Collider> make_collider(const nlohmann::json& j, const std::string& path) {
  using Parser =
      std::function<std::unique_ptr<Collider>(const nlohmann::json&, const std::string&)>;
  static const std::map<std::string, Parser> kinds = {
      {"plane", PlaneCollider::parse},
      {"box", BoxCollider::parse},
      {"cylinder", CylinderCollider::parse},
  };
  json::require_object(j, path);
  std::string type = json::get_string(j, path, "type");
  auto it = kinds.find(type);
  if (it == kinds.end()) {
    std::string known;
    for (const auto& [k, p] : kinds) known += (known.empty() ? "" : ", ") + k;
    fail("scene: '", json::child(path, "type"), "' = \"", type,
         "\" is not a collider (known: ", known, ")");
  }
  return it->second(j, path);
}

}  // namespace nsf
