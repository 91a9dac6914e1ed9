#pragma once
// Inside/outside and distance queries on a triangle mesh, accelerated by a bounding-volume
// hierarchy.
//
// Inside test: the generalised winding number w(q) = Σ Ω_t(q) / 4π (Jacobson, Kavan &
// Sorkine-Hornung 2013), the signed solid angles of the triangles seen from q. It is 1 inside and
// 0 outside a closed, outward-oriented surface and degrades smoothly where the surface is open:
// a hole only removes its own solid angle, which stays below 2π (w > ½) from every interior
// point, so thresholding at ½ ignores small holes. It needs consistent orientation, which
// orient_outward provides. (Ray parity, the other orientation-independent choice, flips the
// answer for every point whose ray leaves through a hole; near a hole that is a finite fraction
// of the directions, so a majority vote over a few rays does not remove the error.)
//
// Speed: far from a BVH node, its triangles' solid angles are replaced by the dipole term
// (p − q)·N / |p − q|³ of their area-weighted centre p and summed area vector N (Barill et al.
// 2018, "Fast winding numbers for soups and clouds", first order). Near nodes are summed exactly.
#include <vector>

#include "mpm/scene/geometry.h"
#include "mpm/scene/mesh/triangle_mesh.h"

namespace nsf {

class WindingBvh {
 public:
  explicit WindingBvh(const TriangleMesh& mesh);

  double winding_number(const Vec3& q) const;
  // The exact winding number by summing every triangle (for tests of the fast one).
  double winding_number_exact(const Vec3& q) const;
  // Unsigned distance from q to the nearest triangle.
  double distance(const Vec3& q) const;
  const Aabb& bounds() const { return nodes_.front().box; }

 private:
  struct Node {
    Aabb box;
    Vec3 centre;                // area-weighted centroid of the node's triangles
    Vec3 area_normal;           // Σ area · unit normal
    double radius;              // every triangle of the node lies within this distance of centre
    int left = -1, right = -1;  // children; -1 for a leaf
    int first = 0, count = 0;   // leaf: triangles order_[first, first + count)
  };

  int build(int first, int count);
  double solid_angle(int t, const Vec3& q) const;

  std::vector<Vec3> a_, b_, c_;  // triangle corners
  std::vector<int> order_;       // triangle indices grouped by leaf
  std::vector<Node> nodes_;      // nodes_[0] is the root
};

}  // namespace nsf
