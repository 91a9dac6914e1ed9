#pragma once
// The keys a scene may use at the top level and in each object. Shared by the validator and by
// the override broadcast rule ("material.E=5" applies to every object).
#include <string>
#include <vector>

namespace nsf {

inline const std::vector<std::string>& top_level_keys() {
  static const std::vector<std::string> keys = {"name",      "description", "simulation", "objects",
                                                "colliders", "sweep",       "camera",     "rom",
                                                "train",     "generalize"};
  return keys;
}

inline const std::vector<std::string>& object_keys() {
  static const std::vector<std::string> keys = {"shape",    "material",         "density",
                                                "velocity", "angular_velocity", "weak_regions"};
  return keys;
}

}  // namespace nsf
