#include <limits>

#include "core/error.h"
#include "core/json_parse.h"
#include "core/json_util.h"
#include "mpm/scene/object_builder.h"
#include "mpm/scene/scene.h"
#include "mpm/scene/scene_keys.h"
#include "mpm/scene/settings_json.h"

namespace nsf {

Scene build_scene(const nlohmann::json& j, const std::string& base_dir) {
  namespace js = nsf::json;
  // Every top-level key is known here; the sections the engine does not read ("sweep", "rom",
  // "train", "generalize") are their owners' to parse (scene.h).
  js::check_keys(j, "", top_level_keys());
  Scene scene;
  scene.name = js::get_string(j, "", "name", "scene");
  js::get_string(j, "", "description", "");  // free text, but it must be text

  if (!j.contains("simulation")) fail("scene: missing required key 'simulation'");
  scene.settings = parse_settings(j.at("simulation"), "simulation");

  if (!j.contains("objects")) fail("scene: missing required key 'objects'");
  const nlohmann::json& objects = j.at("objects");
  if (!objects.is_array() || objects.empty())
    fail("scene: 'objects' must be a non-empty array of objects, got ", objects.dump());
  if (objects.size() > std::numeric_limits<uint16_t>::max())
    fail("scene: 'objects' has ", objects.size(), " entries; at most ",
         std::numeric_limits<uint16_t>::max(), " are supported");
  for (size_t i = 0; i < objects.size(); ++i)
    add_object(objects[i], js::child("objects", i), i, ShapeContext{base_dir}, scene);

  if (j.contains("colliders")) {
    const nlohmann::json& colliders = j.at("colliders");
    if (!colliders.is_array()) fail("scene: 'colliders' must be an array, got ", colliders.dump());
    for (size_t i = 0; i < colliders.size(); ++i)
      scene.colliders.push_back(make_collider(colliders[i], js::child("colliders", i)));
  }
  scene.camera = parse_camera(j);
  // The scene keeps its JSON as provenance. Copying recurses once per level, so a value built in
  // memory (a file is checked as it is parsed) must not nest deeper than a file may; the sections'
  // own parsers name a too-deep key first (a CSG shape: 64 levels).
  if (js::nested_deeper_than(j, js::kMaxJsonDepth))
    fail("scene: nested more than ", js::kMaxJsonDepth, " levels deep");
  scene.source = j;
  return scene;
}

}  // namespace nsf
