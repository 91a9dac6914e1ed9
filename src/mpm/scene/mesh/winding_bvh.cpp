#include "mpm/scene/mesh/winding_bvh.h"

#include <algorithm>
#include <cmath>

namespace nsf {

namespace {

constexpr int kLeafSize = 8;
// A node counts as far when q is more than kFar node radii from its centre. At 3 the first-order
// error of a far node is a few per cent of its own (already small) contribution; the inside test
// only needs w on the right side of ½.
constexpr double kFar = 3.0;
constexpr double kFourPi = 4.0 * M_PI;

double box_distance_sq(const Aabb& b, const Vec3& q) {
  Vec3 d = (b.lo - q).cwiseMax(q - b.hi).cwiseMax(Vec3::Zero());
  return d.squaredNorm();
}

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection, §5.1.5).
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

}  // namespace

WindingBvh::WindingBvh(const TriangleMesh& mesh) {
  const size_t nt = mesh.triangles.size();
  a_.resize(nt), b_.resize(nt), c_.resize(nt);
  order_.resize(nt);
  for (size_t t = 0; t < nt; ++t) {
    a_[t] = mesh.vertices[mesh.triangles[t][0]];
    b_[t] = mesh.vertices[mesh.triangles[t][1]];
    c_[t] = mesh.vertices[mesh.triangles[t][2]];
    order_[t] = int(t);
  }
  nodes_.reserve(2 * nt / kLeafSize + 2);
  build(0, int(nt));
}

int WindingBvh::build(int first, int count) {
  const int id = int(nodes_.size());
  nodes_.emplace_back();
  Node node;
  node.first = first;
  node.count = count;
  Aabb centroids;
  Vec3 weighted = Vec3::Zero(), normal = Vec3::Zero();
  double area = 0;
  for (int i = first; i < first + count; ++i) {
    const int t = order_[i];
    node.box.extend(a_[t]), node.box.extend(b_[t]), node.box.extend(c_[t]);
    const Vec3 centroid = (a_[t] + b_[t] + c_[t]) / 3.0;
    centroids.extend(centroid);
    const Vec3 n = 0.5 * (b_[t] - a_[t]).cross(c_[t] - a_[t]);
    normal += n;
    weighted += n.norm() * centroid;
    area += n.norm();
  }
  node.area_normal = normal;
  node.centre = area > 0 ? Vec3(weighted / area) : Vec3(0.5 * (node.box.lo + node.box.hi));
  node.radius = 0;
  for (int i = first; i < first + count; ++i) {
    const int t = order_[i];
    for (const Vec3* v : {&a_[t], &b_[t], &c_[t]})
      node.radius = std::max(node.radius, (*v - node.centre).norm());
  }
  if (count > kLeafSize) {
    // Median split along the longest axis of the triangle centroids.
    int axis;
    (centroids.hi - centroids.lo).maxCoeff(&axis);
    const int mid = first + count / 2;
    auto key = [&](int t) { return a_[t][axis] + b_[t][axis] + c_[t][axis]; };
    std::nth_element(order_.begin() + first, order_.begin() + mid, order_.begin() + first + count,
                     [&](int s, int t) { return key(s) < key(t); });
    node.left = build(first, mid - first);
    node.right = build(mid, first + count - mid);
  }
  nodes_[id] = node;
  return id;
}

double WindingBvh::solid_angle(int t, const Vec3& q) const {
  // Van Oosterom & Strackee (1983): tan(Ω/2) = a·(b×c) / (|a||b||c| + (a·b)|c| + (b·c)|a| +
  // (c·a)|b|), with a, b, c the corners relative to q.
  const Vec3 a = a_[t] - q, b = b_[t] - q, c = c_[t] - q;
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double num = a.dot(b.cross(c));
  const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
  return 2.0 * std::atan2(num, den);
}

double WindingBvh::winding_number(const Vec3& q) const {
  double w = 0;
  int stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    const Vec3 r = n.centre - q;
    const double d = r.norm();
    if (d > kFar * n.radius) {
      w += r.dot(n.area_normal) / (d * d * d);
    } else if (n.left < 0) {
      for (int i = n.first; i < n.first + n.count; ++i) w += solid_angle(order_[i], q);
    } else {
      stack[top++] = n.left;
      stack[top++] = n.right;
    }
  }
  return w / kFourPi;
}

double WindingBvh::winding_number_exact(const Vec3& q) const {
  double w = 0;
  for (size_t t = 0; t < a_.size(); ++t) w += solid_angle(int(t), q);
  return w / kFourPi;
}

double WindingBvh::distance(const Vec3& q) const {
  double best = std::numeric_limits<double>::infinity();
  int stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (box_distance_sq(n.box, q) >= best) continue;
    if (n.left < 0) {
      for (int i = n.first; i < n.first + n.count; ++i) {
        const int t = order_[i];
        best = std::min(best, (closest_on_triangle(q, a_[t], b_[t], c_[t]) - q).squaredNorm());
      }
      continue;
    }
    // Visit the nearer child first (pushed last) so the bound tightens early.
    int near = n.left, far = n.right;
    if (box_distance_sq(nodes_[far].box, q) < box_distance_sq(nodes_[near].box, q))
      std::swap(near, far);
    stack[top++] = far;
    stack[top++] = near;
  }
  return std::sqrt(best);
}

}  // namespace nsf
