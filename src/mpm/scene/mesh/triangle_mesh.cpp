#include "mpm/scene/mesh/triangle_mesh.h"

#include <map>

namespace nsf {

void weld_vertices(TriangleMesh& mesh) {
  // An ordered map on exact coordinates: deterministic, and exact because shared corners are
  // written (and parsed) as the same number.
  auto less = [](const Vec3& a, const Vec3& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  };
  std::map<Vec3, int, decltype(less)> index(less);
  std::vector<Vec3> welded;
  std::vector<int> remap(mesh.vertices.size());
  for (size_t v = 0; v < mesh.vertices.size(); ++v) {
    auto [it, inserted] = index.emplace(mesh.vertices[v], static_cast<int>(welded.size()));
    if (inserted) welded.push_back(mesh.vertices[v]);
    remap[v] = it->second;
  }
  std::vector<std::array<int, 3>> kept;
  kept.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    std::array<int, 3> w = {remap[t[0]], remap[t[1]], remap[t[2]]};
    if (w[0] != w[1] && w[1] != w[2] && w[2] != w[0]) kept.push_back(w);
  }
  mesh.vertices = std::move(welded);
  mesh.triangles = std::move(kept);
}

}  // namespace nsf
