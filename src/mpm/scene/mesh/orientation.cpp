#include "mpm/scene/mesh/orientation.h"

#include <algorithm>
#include <map>
#include <queue>
#include <utility>

namespace nsf {

namespace {

struct EdgeUse {
  int triangle;
  bool forward;  // the triangle traverses the edge from its lower to its higher vertex index
};

// Does triangle t traverse edge (a, b) as a → b?
bool traverses(const std::array<int, 3>& t, int a, int b) {
  for (int k = 0; k < 3; ++k)
    if (t[k] == a && t[(k + 1) % 3] == b) return true;
  return false;
}

}  // namespace

size_t orient_outward(TriangleMesh& mesh) {
  auto& tris = mesh.triangles;
  const size_t nt = tris.size();
  std::map<std::pair<int, int>, std::vector<EdgeUse>> edges;
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      int a = tris[t][k], b = tris[t][(k + 1) % 3];
      edges[{std::min(a, b), std::max(a, b)}].push_back({int(t), a < b});
    }

  // Breadth-first over manifold edges: a neighbour that traverses the shared edge the same way
  // as the (already fixed) current triangle is wound the other way round and gets flipped.
  std::vector<int> component(nt, -1);
  std::vector<char> flipped(nt, 0);
  int components = 0;
  for (size_t seed = 0; seed < nt; ++seed) {
    if (component[seed] >= 0) continue;
    std::queue<int> queue;
    queue.push(int(seed));
    component[seed] = components;
    while (!queue.empty()) {
      int t = queue.front();
      queue.pop();
      for (int k = 0; k < 3; ++k) {
        int a = tris[t][k], b = tris[t][(k + 1) % 3];
        const auto& uses = edges[{std::min(a, b), std::max(a, b)}];
        if (uses.size() != 2) continue;  // boundary (a hole) or non-manifold: no constraint
        int n = uses[0].triangle == t ? uses[1].triangle : uses[0].triangle;
        if (component[n] >= 0) continue;
        component[n] = components;
        if (traverses(tris[n], a, b)) {
          std::swap(tris[n][1], tris[n][2]);
          flipped[n] = 1;
        }
        queue.push(n);
      }
    }
    ++components;
  }

  // Signed volume of each component, about its own vertex mean so that a hole (which leaves the
  // surface open) biases the sum as little as possible.
  std::vector<Vec3> centre(components, Vec3::Zero());
  std::vector<double> count(components, 0.0), volume(components, 0.0);
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      centre[component[t]] += mesh.vertices[tris[t][k]];
      count[component[t]] += 1;
    }
  for (int c = 0; c < components; ++c) centre[c] /= count[c];
  for (size_t t = 0; t < nt; ++t) {
    const Vec3& o = centre[component[t]];
    Vec3 a = mesh.vertices[tris[t][0]] - o, b = mesh.vertices[tris[t][1]] - o,
         c = mesh.vertices[tris[t][2]] - o;
    volume[component[t]] += a.dot(b.cross(c)) / 6.0;
  }
  size_t changed = 0;
  for (size_t t = 0; t < nt; ++t) {
    if (volume[component[t]] < 0) {
      std::swap(tris[t][1], tris[t][2]);
      flipped[t] ^= 1;
    }
    changed += flipped[t];
  }
  return changed;
}

}  // namespace nsf
