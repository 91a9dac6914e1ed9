#pragma once
// Dense background grid over the scene domain. Node (i,j,k) sits at domain_lo + (i,j,k)·dx.
// Each node stores momentum (then velocity) and mass contiguously for the scatter in P2G.
#include <vector>

#include "core/types.h"

namespace nsf {

struct GridNode {
  double mv[3];  // momentum in P2G; velocity after the grid update
  double m;
};

class Grid {
 public:
  Grid() = default;
  Grid(const Vec3& lo, const Vec3& hi, double dx);

  Vec3i dims() const { return n_; }
  size_t node_count() const { return nodes_.size(); }
  double dx() const { return dx_; }
  double inv_dx() const { return inv_dx_; }
  const Vec3& lo() const { return lo_; }

  size_t index(int i, int j, int k) const {
    return (static_cast<size_t>(i) * n_[1] + j) * static_cast<size_t>(n_[2]) + k;
  }
  Vec3 node_position(int i, int j, int k) const { return lo_ + Vec3(i, j, k) * dx_; }

  GridNode* data() { return nodes_.data(); }
  const GridNode* data() const { return nodes_.data(); }
  GridNode& operator[](size_t i) { return nodes_[i]; }
  const GridNode& operator[](size_t i) const { return nodes_[i]; }

 private:
  Vec3 lo_ = Vec3::Zero();
  double dx_ = 1, inv_dx_ = 1;
  Vec3i n_ = Vec3i::Zero();
  std::vector<GridNode> nodes_;
};

}  // namespace nsf
