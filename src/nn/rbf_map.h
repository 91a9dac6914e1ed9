#pragma once
// Coefficients as a thin-plate-spline interpolant of the training latents (docs/TRAINING.md,
// "Coefficient maps"): for an input y (the latent, and μ or the latent velocity where the field
// takes them), scaled per component to the training rows' spread,
//     c(y) = Σ_i w_i φ(‖y − y_i‖) + a_0 + A y,      φ(ρ) = ρ² log ρ,
// over the N training rows y_i, with (Φ + s I) w + P a = c_train and Pᵀ w = 0. It holds the
// training rows' coefficients to within the smoothing s, is smooth between them, holds inputs to
// the training rows' box (plus half a spread), and costs
// N·(d + K) multiply-adds per evaluation: nothing beside the per-point products. Without torch.
#include <Eigen/Core>
#include <vector>

namespace nsf {

struct RbfMap {
  Eigen::MatrixXd centers;       // N × d, scaled inputs
  Eigen::MatrixXd weights;       // N × K
  Eigen::MatrixXd poly;          // (d + 1) × K: the constant, then the linear terms
  Eigen::VectorXd shift, scale;  // d: y = (x − shift) / scale
  double smoothing = 0;

  bool empty() const { return centers.rows() == 0; }
  int64_t inputs() const { return centers.cols(); }
  int64_t outputs() const { return weights.cols(); }
  // c(x); with J, also ∂c/∂x (outputs × inputs).
  Eigen::VectorXd operator()(const Eigen::VectorXd& x, Eigen::MatrixXd* J = nullptr) const;
};

struct RbfFitReport {
  double smoothing = 0;
  // Each row predicted by the map fitted without its group's fold (leave-groups-out
  // cross-validation): the median over the groups of Σ‖c − c_train‖² / Σ‖c_train‖² over the
  // group's rows, at the chosen smoothing; NaN with one group.
  double cv_error = 0;
  int folds = 0;
};

// The map through `targets` (N × K) at `inputs` (N × d), its smoothing chosen from a fixed grid
// by cross-validation over `group` (one id per row: the training run it came from), so that the
// map is judged on runs it did not see, as at a held-out μ; by the median run, so that one run
// that no other predicts does not choose for all.
RbfMap fit_rbf(const Eigen::MatrixXd& inputs, const Eigen::MatrixXd& targets,
               const std::vector<int>& group, RbfFitReport* report = nullptr);

}  // namespace nsf
