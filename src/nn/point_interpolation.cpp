#include "nn/point_interpolation.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "core/error.h"

namespace nsf {

namespace {

// The particles bucketed in a uniform grid of about two particles per cell, for k-nearest queries.
class ParticleGrid {
 public:
  explicit ParticleGrid(const std::vector<Vec3>& X) : X_(X) {
    lo_ = X[0], hi_ = X[0];
    for (const Vec3& p : X) lo_ = lo_.cwiseMin(p), hi_ = hi_.cwiseMax(p);
    const Vec3 extent = (hi_ - lo_).cwiseMax(1e-12);
    cell_ = std::cbrt(2.0 * extent.prod() / double(X.size()));
    cell_ = std::max(cell_, 1e-6 * extent.maxCoeff());
    for (uint32_t i = 0; i < X.size(); ++i) cells_[key(X[i])].push_back(i);
  }
  double extent() const { return (hi_ - lo_).maxCoeff(); }

  // The k nearest particles of x, nearest first, with their distances.
  void nearest(const Vec3& x, size_t k, std::vector<std::pair<double, uint32_t>>& out) const {
    out.clear();
    const Eigen::Vector3i c = cell_of(x);
    for (int ring = 0;; ++ring) {
      for (int i = -ring; i <= ring; ++i)
        for (int j = -ring; j <= ring; ++j)
          for (int l = -ring; l <= ring; ++l) {
            if (std::max({std::abs(i), std::abs(j), std::abs(l)}) != ring) continue;
            const auto it = cells_.find(pack(c + Eigen::Vector3i(i, j, l)));
            if (it == cells_.end()) continue;
            for (uint32_t p : it->second) out.emplace_back((X_[p] - x).norm(), p);
          }
      // Every particle within ring·cell of x has been seen: stop once k of them are that near.
      if (out.size() >= std::min(k, X_.size())) {
        std::sort(out.begin(), out.end());
        if (out[std::min(k, out.size()) - 1].first <= ring * cell_ || out.size() == X_.size()) {
          out.resize(std::min(k, out.size()));
          return;
        }
      }
      if (ring > 4096)
        fail("interpolation: no particles near (", x[0], ", ", x[1], ", ", x[2], ")");
    }
  }

 private:
  Eigen::Vector3i cell_of(const Vec3& x) const {
    return ((x - lo_) / cell_).array().floor().cast<int>().matrix();
  }
  static int64_t pack(const Eigen::Vector3i& c) {
    return (int64_t(c[0] + (1 << 20)) << 42) | (int64_t(c[1] + (1 << 20)) << 21) |
           int64_t(c[2] + (1 << 20));
  }
  int64_t key(const Vec3& x) const { return pack(cell_of(x)); }

  const std::vector<Vec3>& X_;
  Vec3 lo_, hi_;
  double cell_ = 1;
  std::unordered_map<int64_t, std::vector<uint32_t>> cells_;
};

double cubic_spline(double q) {  // support [0, 1)
  if (q >= 1) return 0;
  return q < 0.5 ? 1 - 6 * q * q + 6 * q * q * q : 2 * (1 - q) * (1 - q) * (1 - q);
}

}  // namespace

PointInterpolation interpolate_points(const std::vector<Vec3>& particles,
                                      const std::vector<Vec3>& points, const std::string& scheme,
                                      int neighbours) {
  if (scheme != "nearest" && scheme != "mls")
    fail("interpolation: unknown scheme '", scheme, "' (known: nearest, mls)");
  if (particles.empty()) fail("interpolation: no particles to interpolate from");
  const ParticleGrid grid(particles);
  const double same = 1e-9 * std::max(grid.extent(), 1e-12);
  PointInterpolation out;
  out.start.push_back(0);
  std::vector<std::pair<double, uint32_t>> near;
  for (const Vec3& x : points) {
    grid.nearest(x, scheme == "nearest" ? 1 : size_t(std::max(4, neighbours)), near);
    if (scheme == "nearest" || near[0].first <= same || near.size() < 4) {
      out.particle.push_back(near[0].second), out.weight.push_back(1.0f);
    } else {
      // Linear MLS: minimise Σ w_i (f_i − a − b·(X_i − x))²; f(x) = a is linear in the f_i, with
      // weights the first row of (MᵀWM)⁻¹MᵀW. The support reaches just past the farthest one.
      const double h = 1.0001 * near.back().first;
      Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
      std::vector<Eigen::Vector4d> m(near.size());
      std::vector<double> w(near.size());
      for (size_t i = 0; i < near.size(); ++i) {
        const Vec3 d = particles[near[i].second] - x;
        m[i] << 1, d[0], d[1], d[2];
        w[i] = cubic_spline(near[i].first / h);
        A += w[i] * m[i] * m[i].transpose();
      }
      // Scale-free regularisation: particles on a plane (a thin sheet) leave A singular.
      A.diagonal().tail<3>().array() += 1e-6 * A(0, 0) * h * h;
      const Eigen::Vector4d e = A.ldlt().solve(Eigen::Vector4d::UnitX());
      for (size_t i = 0; i < near.size(); ++i) {
        const double wi = w[i] * e.dot(m[i]);
        if (wi == 0) continue;
        out.particle.push_back(near[i].second), out.weight.push_back(float(wi));
      }
    }
    out.start.push_back(uint32_t(out.particle.size()));
  }
  return out;
}

}  // namespace nsf
