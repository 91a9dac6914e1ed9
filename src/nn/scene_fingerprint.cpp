#include "nn/scene_fingerprint.h"

#include <cstdio>
#include <sstream>

#include "core/error.h"

namespace nsf {

std::string hex64(uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

SceneFingerprint SceneFingerprint::of(const std::string& scene_name, const std::vector<Vec3>& X) {
  // FNV-1a over the raw doubles: any change to the sampling (resolution, seed, geometry) changes
  // the particle indexing and must invalidate the model.
  uint64_t h = 1469598103934665603ull;
  for (const Vec3& p : X) {
    const unsigned char* b = reinterpret_cast<const unsigned char*>(p.data());
    for (size_t i = 0; i < 3 * sizeof(double); ++i) h = (h ^ b[i]) * 1099511628211ull;
  }
  return {scene_name, static_cast<int64_t>(X.size()), h};
}

std::string SceneFingerprint::describe() const {
  std::ostringstream os;
  os << "scene '" << scene_name << "' (" << particles << " particles, X hash " << hex64(x_hash)
     << ")";
  return os.str();
}

void check_same_scene(const SceneFingerprint& model, const SceneFingerprint& data,
                      const std::string& what) {
  if (!model.matches(data))
    fail("the model was trained for ", model.describe(), ", but ", what, " is ", data.describe(),
         "; train a model for this scene (nsf train)");
}

}  // namespace nsf
