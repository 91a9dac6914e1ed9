#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/types.h"

namespace nsf {

// Identifies the scene a model belongs to: the reference positions X fix the particle indexing
// every network relies on, so the hash covers their exact bits.
struct SceneFingerprint {
  std::string scene_name;
  int64_t particles = 0;
  uint64_t x_hash = 0;

  static SceneFingerprint of(const std::string& scene_name, const std::vector<Vec3>& X);
  bool matches(const SceneFingerprint& o) const {
    return particles == o.particles && x_hash == o.x_hash;
  }
  std::string describe() const;  // "scene 'bread' (40000 particles, X hash 0123abcd…)"
};

// Throws nsf::Error unless `data` (what `what` is: a run file, a scene) is the scene `model` was
// trained for.
void check_same_scene(const SceneFingerprint& model, const SceneFingerprint& data,
                      const std::string& what);

// 16 hex digits.
std::string hex64(uint64_t v);

}  // namespace nsf
