// GCC 12 reports false -Wmaybe-uninitialized warnings from inside Eigen's AVX-512 kernels for
// dynamic-size products (in the intrinsics headers, not in this code).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include "rom/inversion/latent_prior.h"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/error.h"

namespace nsf {

LatentPrior::LatentPrior(const std::vector<std::vector<Eigen::VectorXd>>& runs,
                         const Eigen::VectorXd& spread)
    : spread_(spread) {
  if (runs.empty() || runs[0].empty()) fail("latent prior: the model stores no training latents");
  size_t frames = runs[0].size();
  for (const auto& run : runs) frames = std::min(frames, run.size());
  if (frames == 0) fail("latent prior: a training run without latents");
  if (!(spread_.size() == runs[0][0].size() && (spread_.array() > 0).all() && spread_.allFinite()))
    fail("latent prior: the latent spreads must be ", runs[0][0].size(), " positive numbers");
  for (const auto& run : runs)
    for (size_t i = 0; i < frames; ++i) {
      if (run[i].size() != spread_.size() || !run[i].allFinite())
        fail("latent prior: training latents of unequal dimension or not finite");
      w_.push_back(whiten(run[i]));
    }

  const auto add = [&](size_t a, size_t b, size_t c) {
    Triangle t{int(a), int(b), int(c), w_[b] - w_[a], w_[c] - w_[a], {}, 0, 0, 0, 0};
    t.side[0] = t.e1, t.side[1] = w_[c] - w_[b], t.side[2] = -t.e2;
    t.a11 = t.e1.squaredNorm(), t.a12 = t.e1.dot(t.e2), t.a22 = t.e2.squaredNorm();
    t.det = t.a11 * t.a22 - t.a12 * t.a12;
    tri_.push_back(std::move(t));
  };
  // The grid of runs × frames, two triangles per cell. With one run (or one frame per run) the
  // grid is a polyline, kept as degenerate triangles whose edges are its segments.
  const auto id = [&](size_t j, size_t i) { return j * frames + i; };
  const size_t n_runs = runs.size();
  if (n_runs == 1 && frames == 1) add(0, 0, 0);
  for (size_t j = 0; j < n_runs; ++j)
    for (size_t i = 0; i < frames; ++i) {
      const bool next_run = j + 1 < n_runs, next_frame = i + 1 < frames;
      if (next_run && next_frame) {
        add(id(j, i), id(j + 1, i), id(j, i + 1));
        add(id(j + 1, i), id(j + 1, i + 1), id(j, i + 1));
      } else if (next_frame && n_runs == 1) {
        add(id(j, i), id(j, i + 1), id(j, i + 1));
      } else if (next_run && frames == 1) {
        add(id(j, i), id(j + 1, i), id(j + 1, i));
      }
    }
  centers_.resize(spread_.size(), Eigen::Index(tri_.size()));
  radii_.resize(Eigen::Index(tri_.size()));
  for (size_t i = 0; i < tri_.size(); ++i) {
    const Triangle& t = tri_[i];
    const Eigen::Index col = Eigen::Index(i);
    centers_.col(col) = (w_[size_t(t.a)] + w_[size_t(t.b)] + w_[size_t(t.c)]) / 3.0;
    radii_[col] = 0;
    for (int k : {t.a, t.b, t.c})
      radii_[col] = std::max(radii_[col], (w_[size_t(k)] - centers_.col(col)).norm());
  }
}

// Distances are all that count, so no mean is taken off: scaling each component is enough.
Eigen::VectorXd LatentPrior::whiten(const Eigen::VectorXd& z) const {
  return z.cwiseQuotient(spread_);
}

double LatentPrior::closest(const Eigen::VectorXd& w, Eigen::VectorXd* point,
                            Eigen::MatrixXd* plane) const {
  // No distance to a NaN compares smaller than infinity: no triangle would be the closest.
  if (!w.allFinite())
    fail(
        "latent prior: the latent holds a NaN or infinite value (a damaged model, or a state "
        "that diverged)");
  // The best feature: a triangle's interior (edge = -1) or one of its edges (0, 1, 2), with the
  // parameters of the closest point on it.
  double best = std::numeric_limits<double>::infinity();
  const Triangle* best_tri = nullptr;
  int best_edge = -1;
  double best_s = 0, best_u = 0;
  Eigen::VectorXd d(w.size());  // reused: this loop is on the inversion's every iteration
  // No point of a triangle is nearer than its ball allows, and the surface comes at least as
  // near as the corners of the last call's closest triangle: the triangles whose ball is farther
  // than those corners are skipped (the metal_small ROM's inversion time halves). The others
  // are scanned in order, as every triangle was before, so ties and results are the same.
  const size_t hint = std::min(hint_.load(std::memory_order_relaxed), tri_.size() - 1);
  double reach = std::numeric_limits<double>::infinity();
  for (int k : {tri_[hint].a, tri_[hint].b, tri_[hint].c})
    reach = std::min(reach, (w - w_[size_t(k)]).squaredNorm());
  // Each ball's gap to w, shrunk by far more than rounding could add to it, so that a triangle
  // that ties for the closest is never skipped; the hint's own triangle is always scanned.
  const Eigen::ArrayXd centre = (centers_.colwise() - w).colwise().norm().transpose().array();
  const Eigen::ArrayXd gap = (centre - radii_ - 1e-9 * (centre + radii_)).max(0.0);
  for (size_t i = 0; i < tri_.size(); ++i) {
    if (i != hint && gap[Eigen::Index(i)] * gap[Eigen::Index(i)] > reach) continue;
    const Triangle& t = tri_[i];
    d = w - w_[size_t(t.a)];
    if (t.det > 1e-12 * t.a11 * t.a22) {
      const double b1 = t.e1.dot(d), b2 = t.e2.dot(d);
      const double s = (t.a22 * b1 - t.a12 * b2) / t.det, u = (t.a11 * b2 - t.a12 * b1) / t.det;
      if (s >= 0 && u >= 0 && s + u <= 1) {
        const double dist = (d - s * t.e1 - u * t.e2).squaredNorm();
        if (dist < best) best = dist, best_tri = &t, best_edge = -1, best_s = s, best_u = u;
        continue;  // inside: no edge of this triangle is closer
      }
    }
    const Eigen::VectorXd* start[3] = {&w_[size_t(t.a)], &w_[size_t(t.b)], &w_[size_t(t.c)]};
    for (int k = 0; k < 3; ++k) {  // side k runs from corner k to the next
      const Eigen::VectorXd &p0 = *start[k], &e = t.side[k];
      const double ee = e.squaredNorm();
      const double s = ee > 0 ? std::clamp((w - p0).dot(e) / ee, 0.0, 1.0) : 0.0;
      const double dist = (w - p0 - s * e).squaredNorm();
      if (dist < best) best = dist, best_tri = &t, best_edge = k, best_s = s;
    }
  }
  hint_.store(size_t(best_tri - tri_.data()), std::memory_order_relaxed);
  if (!point) return best;
  const Triangle& t = *best_tri;
  const Eigen::Index r = w.size();
  if (best_edge < 0) {
    *point = w_[size_t(t.a)] + best_s * t.e1 + best_u * t.e2;
    Eigen::MatrixXd E(r, 2);
    E << t.e1, t.e2;
    *plane =
        Eigen::HouseholderQR<Eigen::MatrixXd>(E).householderQ() * Eigen::MatrixXd::Identity(r, 2);
    return best;
  }
  const int start[3] = {t.a, t.b, t.c};
  *point = w_[size_t(start[best_edge])] + best_s * t.side[best_edge];
  if (best_s > 0 && best_s < 1)
    *plane = t.side[best_edge].normalized();
  else
    plane->resize(r, 0);
  return best;
}

double LatentPrior::distance2(const Eigen::VectorXd& z) const {
  return closest(whiten(z), nullptr, nullptr);
}

LatentPrior::Nearest LatentPrior::nearest(const Eigen::VectorXd& z) const {
  const Eigen::VectorXd w = whiten(z);
  Eigen::VectorXd p;
  Eigen::MatrixXd T;
  Nearest n;
  n.distance2 = closest(w, &p, &T);
  // In whitened coordinates d² = ‖(I − TTᵀ)(w − p)‖² near the closest point; w = D⁻¹ẑ.
  const Eigen::VectorXd inv = spread_.cwiseInverse();
  n.gradient = inv.cwiseProduct(w - p);
  const Eigen::MatrixXd normal = Eigen::MatrixXd::Identity(w.size(), w.size()) - T * T.transpose();
  n.hessian = inv.asDiagonal() * normal * inv.asDiagonal();
  return n;
}

// The training runs' latents, in order of μ: the surface the latent prior holds the inversion near.
// Each latent component's spread over them is the unit in which the distance is measured.
std::unique_ptr<LatentPrior> training_latent_prior(const ModelRecord& m) {
  if (m.trajectory_latents.empty()) return nullptr;
  std::vector<size_t> order(m.trajectory_latents.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return m.trajectory_mu[a] < m.trajectory_mu[b]; });
  std::vector<std::vector<Eigen::VectorXd>> runs;
  for (size_t j : order) runs.push_back(m.trajectory_latents[j]);
  return std::make_unique<LatentPrior>(runs, m.latent_spread);
}

}  // namespace nsf
