#include "rom/step/integration_set.h"

#include <algorithm>
#include <cmath>

namespace nsf {

NodeMarks::NodeMarks(const Vec3& lo, double dx, const Vec3i& dims)
    : lo_(lo), inv_dx_(1.0 / dx), dims_(dims), flag_(size_t(dims[0]) * dims[1] * dims[2], 0) {}

void NodeMarks::clear() {
  for (uint32_t i : set_) flag_[i] = 0;
  set_.clear();
}

void NodeMarks::stencil_base(const Vec3& x, int base[3]) const {
  // Same base as quadratic_stencil (mpm/bspline.h): floor(x/dx − 0.5). Clamped so that a
  // position outside the grid (a diverged latent) still indexes valid memory; the stepper's
  // guard reports such positions.
  for (int d = 0; d < 3; ++d) {
    const double c = (x[d] - lo_[d]) * inv_dx_ - 0.5;
    const double f = std::isfinite(c) ? std::floor(c) : 0.0;
    base[d] = int(std::clamp(f, 0.0, double(std::max(0, dims_[d] - 3))));
  }
}

void NodeMarks::mark_stencils(const std::vector<Vec3>& x, int halo) {
  const size_t sj = dims_[2], si = size_t(dims_[1]) * dims_[2];
  for (const Vec3& p : x) {
    int b[3];
    stencil_base(p, b);
    int lo[3], hi[3];
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::max(0, b[d] - halo);
      hi[d] = std::min(dims_[d] - 1, b[d] + 2 + halo);
    }
    for (int i = lo[0]; i <= hi[0]; ++i)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int k = lo[2]; k <= hi[2]; ++k) {
          const size_t n = i * si + j * sj + k;
          if (!flag_[n]) flag_[n] = 1, set_.push_back(uint32_t(n));
        }
  }
}

bool NodeMarks::touches(const Vec3& x) const {
  const size_t sj = dims_[2], si = size_t(dims_[1]) * dims_[2];
  int b[3];
  stencil_base(x, b);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const uint8_t* row = &flag_[(b[0] + i) * si + (b[1] + j) * sj + b[2]];
      if (row[0] | row[1] | row[2]) return true;
    }
  return false;
}

std::vector<uint32_t> integration_particles(const NodeMarks& I, const std::vector<Vec3>& x) {
  std::vector<uint32_t> n;
  for (size_t p = 0; p < x.size(); ++p)
    if (I.touches(x[p])) n.push_back(uint32_t(p));
  return n;
}

void CandidateSet::refresh(NodeMarks& scratch, const std::vector<Vec3>& x,
                           const std::vector<Vec3>& samples, const std::vector<uint32_t>* ids) {
  scratch.clear();
  scratch.mark_stencils(samples, halo_);
  const std::vector<uint32_t> rows = integration_particles(scratch, x);
  ids_.resize(rows.size());
  x_ref_.resize(rows.size());
  for (size_t k = 0; k < rows.size(); ++k) {
    ids_[k] = ids ? (*ids)[rows[k]] : rows[k];
    x_ref_[k] = x[rows[k]];
  }
  scratch.clear();
}

bool CandidateSet::stale(const std::vector<Vec3>& x_now, double dx) const {
  // A particle outside K starts ≥ halo nodes from I. For it to reach N, it and the samples
  // (which move I) must close that gap; each moves at most `drift`, and cell rounding can cost
  // one more node, so K stays a superset while 2·drift < (halo − 1)·dx.
  double drift = 0;
  for (size_t k = 0; k < ids_.size(); ++k)
    drift = std::max(drift, (x_now[k] - x_ref_[k]).cwiseAbs().maxCoeff());
  return !(2 * drift < (halo_ - 1) * dx);
}

}  // namespace nsf
