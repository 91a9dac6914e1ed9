// GCC 12 reports false -Wmaybe-uninitialized warnings from inside Eigen's kernels for
// dynamic-size products (in the intrinsics headers, not in this code).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include "nn/rbf_map.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "core/error.h"

namespace nsf {

namespace {

// φ(ρ) = ρ² log ρ from ρ², and φ'(ρ)/ρ = 2 log ρ + 1 (0 at ρ = 0, where φ is flat).
double phi(double rho2) {
  return rho2 > 0 ? 0.5 * rho2 * std::log(rho2) : 0.0;
}
double dphi_over_rho(double rho2) {
  return rho2 > 0 ? std::log(rho2) + 1.0 : 0.0;
}

// The smoothing grid the cross-validation chooses from (inputs scaled to unit spread).
constexpr double kSmoothing[] = {1e-6, 1e-4, 1e-3, 1e-2, 1e-1, 1.0};
constexpr int kMaxFolds = 8;
// How far past the training rows' box (in each input's spread) the map still follows its spline:
// half a spread keeps held-out runs at the edge of the sweep (sand_small's C: 1.6 % against
// 2.8 % with no margin) and still stops a straying latent.
constexpr double kBoxMargin = 0.5;

// Weights and polynomial through rows `rows` of (y, c) with smoothing s.
void solve(const Eigen::MatrixXd& y, const Eigen::MatrixXd& c, const std::vector<int64_t>& rows,
           double s, Eigen::MatrixXd& w, Eigen::MatrixXd& a) {
  const int64_t n = int64_t(rows.size()), d = y.cols(), m = n + d + 1;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(m, m), rhs = Eigen::MatrixXd::Zero(m, c.cols());
  for (int64_t i = 0; i < n; ++i) {
    for (int64_t j = 0; j < i; ++j)
      M(i, j) = M(j, i) = phi((y.row(rows[i]) - y.row(rows[j])).squaredNorm());
    M(i, i) = s;
    M(i, n) = M(n, i) = 1.0;
    for (int64_t k = 0; k < d; ++k) M(i, n + 1 + k) = M(n + 1 + k, i) = y(rows[i], k);
    rhs.row(i) = c.row(rows[i]);
  }
  // A constant input (μ of a dataset without one) has no linear term: pin its coefficient to 0.
  for (int64_t k = 0; k < d; ++k)
    if (M.block(0, n + 1 + k, n, 1).cwiseAbs().maxCoeff() == 0) M(n + 1 + k, n + 1 + k) = 1;
  const Eigen::MatrixXd sol = Eigen::PartialPivLU<Eigen::MatrixXd>(M).solve(rhs);
  w = sol.topRows(n), a = sol.bottomRows(d + 1);
}

Eigen::VectorXd evaluate(const Eigen::MatrixXd& centers, const Eigen::MatrixXd& w,
                         const Eigen::MatrixXd& a, const Eigen::VectorXd& y, Eigen::MatrixXd* dy) {
  const int64_t d = y.size();
  Eigen::VectorXd out = a.row(0).transpose() + a.bottomRows(d).transpose() * y;
  if (dy) *dy = a.bottomRows(d).transpose();
  Eigen::VectorXd e(d);  // once: this runs every ROM step
  for (int64_t i = 0; i < centers.rows(); ++i) {
    e.noalias() = y - centers.row(i).transpose();
    const double rho2 = e.squaredNorm();
    out += phi(rho2) * w.row(i).transpose();
    if (dy) *dy += dphi_over_rho(rho2) * w.row(i).transpose() * e.transpose();
  }
  return out;
}

}  // namespace

Eigen::VectorXd RbfMap::operator()(const Eigen::VectorXd& x, Eigen::MatrixXd* J) const {
  if (x.size() != inputs())
    fail("internal error: a coefficient map of ", inputs(), " inputs given ", x.size());
  // Held to the training rows' box (plus kBoxMargin): a spline grows without bound away from its
  // centres, and a ROM's latent that strays would otherwise be answered with ever larger fields.
  Eigen::VectorXd y = (x - shift).cwiseQuotient(scale), inside = Eigen::VectorXd::Ones(y.size());
  for (int64_t k = 0; k < y.size(); ++k) {
    const double lo = centers.col(k).minCoeff() - kBoxMargin,
                 hi = centers.col(k).maxCoeff() + kBoxMargin;
    if (y[k] < lo || y[k] > hi) y[k] = std::clamp(y[k], lo, hi), inside[k] = 0;
  }
  Eigen::VectorXd c = evaluate(centers, weights, poly, y, J);
  if (J) *J = *J * scale.cwiseInverse().cwiseProduct(inside).asDiagonal();
  return c;
}

RbfMap fit_rbf(const Eigen::MatrixXd& inputs, const Eigen::MatrixXd& targets,
               const std::vector<int>& group, RbfFitReport* report) {
  const int64_t n = inputs.rows(), d = inputs.cols();
  if (n < d + 2 || targets.rows() != n || int64_t(group.size()) != n)
    fail("a coefficient map needs more training rows (", n, ") than inputs (", d,
         ") plus one, and one target and one group per row");
  if (!inputs.allFinite() || !targets.allFinite())
    fail("the coefficient map's training rows hold NaN or infinite values");
  RbfMap m;
  m.shift = inputs.colwise().mean().transpose();
  m.scale = ((inputs.rowwise() - m.shift.transpose()).colwise().squaredNorm() / double(n))
                .cwiseSqrt()
                .transpose();
  for (int64_t k = 0; k < d; ++k)
    if (!(m.scale[k] > 1e-12 * (1 + std::abs(m.shift[k]))))  // a constant input: exactly 0 below
      m.shift[k] = inputs(0, k), m.scale[k] = 1;
  const Eigen::MatrixXd y =
      (inputs.rowwise() - m.shift.transpose()).array().rowwise() / m.scale.transpose().array();

  // Folds: the groups in order of appearance, dealt round-robin over at most kMaxFolds.
  std::map<int, int> fold_of;
  for (int g : group)
    if (!fold_of.count(g)) fold_of.emplace(g, int(fold_of.size()));
  const int folds = std::min<int>(kMaxFolds, int(fold_of.size()));
  // Each smoothing is scored by the median over the training runs of each run's relative error
  // when its fold is left out: a run that no other run predicts (the bread run whose slab tears
  // another way: 394 % at any smoothing) would otherwise decide the smoothing for all the others
  // (bread_small's stress map: 25.2 % on the held-out runs with the sum, 12.6 % with the median).
  double best = std::numeric_limits<double>::infinity(), chosen = kSmoothing[2];
  if (folds >= 2) {
    std::vector<double> norm(fold_of.size(), 0.0);
    for (int64_t i = 0; i < n; ++i) norm[size_t(fold_of[group[i]])] += targets.row(i).squaredNorm();
    for (double s : kSmoothing) {
      std::vector<double> err(fold_of.size(), 0.0);
      for (int f = 0; f < folds; ++f) {
        std::vector<int64_t> fit, out;
        for (int64_t i = 0; i < n; ++i) (fold_of[group[i]] % folds == f ? out : fit).push_back(i);
        if (int64_t(fit.size()) < d + 2) continue;
        Eigen::MatrixXd w, a;
        solve(y, targets, fit, s, w, a);
        Eigen::MatrixXd centers(fit.size(), d);
        for (size_t i = 0; i < fit.size(); ++i) centers.row(int64_t(i)) = y.row(fit[i]);
        for (int64_t i : out)
          err[size_t(fold_of[group[i]])] +=
              (evaluate(centers, w, a, y.row(i).transpose(), nullptr) - targets.row(i).transpose())
                  .squaredNorm();
      }
      for (size_t g = 0; g < err.size(); ++g) err[g] /= std::max(norm[g], 1e-300);
      std::nth_element(err.begin(), err.begin() + long(err.size() / 2), err.end());
      const double median = err[err.size() / 2];
      if (std::isfinite(median) && median < best) best = median, chosen = s;
    }
  }
  std::vector<int64_t> all(static_cast<size_t>(n));
  for (int64_t i = 0; i < n; ++i) all[size_t(i)] = i;
  solve(y, targets, all, chosen, m.weights, m.poly);
  m.centers = y;
  m.smoothing = chosen;
  if (!m.weights.allFinite() || !m.poly.allFinite())
    fail("the coefficient map's fit is singular (", n, " rows of ", d, " inputs)");
  if (report) {
    report->smoothing = chosen;
    report->cv_error = folds >= 2 ? best : std::numeric_limits<double>::quiet_NaN();
    report->folds = folds;
  }
  return m;
}

}  // namespace nsf
