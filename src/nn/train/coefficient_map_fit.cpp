// A basis model's coefficient map (--coefficients map): τ's or C's coefficients as a thin-plate
// spline map through the training latents (nn/rbf_map.h), fitted instead of trained.
#include <cmath>
#include <cstdio>

#include "nn/basis_decoders.h"
#include "nn/basis_export.h"
#include "nn/rbf_map.h"
#include "nn/train/trainer_state.h"

namespace nsf::train {

double Trainer::fit_coefficient_map() {
  const int f = stage_;
  const int64_t rows = latents_.size(0), r = model_.latent_dim();
  // The inputs' layout is the runtime's own: BasisDecoders::stress_input / affine_input.
  BasisDecoders inputs_of = coefficient_inputs(model_);
  const auto input = [&](const Eigen::VectorXd& z, double mu, const Eigen::VectorXd& zdot) {
    return f == 1 ? inputs_of.stress_input(z, mu, &zdot) : inputs_of.affine_input(z, mu, &zdot);
  };
  const bool with_velocity =
      f == 1 ? inputs_of.stress_uses_velocity : inputs_of.affine_uses_velocity;
  const int64_t d = input(Eigen::VectorXd::Zero(r), 0, Eigen::VectorXd::Zero(r)).size();
  const bool with_mu = d > r * (with_velocity ? 2 : 1);
  if (with_velocity) inputs_of.u = point_basis(model_, 0);  // c_u and B_u: the latent velocities
  const torch::Tensor z = latents_.to(torch::kFloat64).contiguous();
  const torch::Tensor c = targets_[f].to(torch::kFloat64).contiguous();
  Eigen::MatrixXd inputs(rows, d), goal(rows, c.size(1));
  std::vector<int> group(static_cast<size_t>(rows));
  for (int64_t i = 0; i < rows; ++i) {
    const size_t frame = size_t(latent_frame_[size_t(i)]);
    const SimulationFile& run = data_.train()[store_.sim_of(frame)];
    const Eigen::Map<const Eigen::VectorXd> zi(z[i].data_ptr<double>(), r);
    Eigen::VectorXd zdot;
    if (with_velocity) {
      const std::vector<float> v = data_.read_field(run, store_.frame_of(frame), "v");
      zdot = inputs_of.latent_velocity(zi, v.data());
    }
    inputs.row(i) = input(zi, run.mu, zdot).transpose();
    goal.row(i) =
        Eigen::Map<const Eigen::VectorXd>(c[int64_t(frame)].data_ptr<double>(), c.size(1));
    group[size_t(i)] = int(store_.sim_of(frame));
  }
  RbfFitReport report;
  const RbfMap m = fit_rbf(inputs, goal, group, &report);
  const auto tensor = [](const Eigen::MatrixXd& a) {
    const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> row = a;
    return torch::from_blob(const_cast<double*>(row.data()), {row.rows(), row.cols()},
                            torch::kFloat64)
        .clone();
  };
  const auto vector = [](const Eigen::VectorXd& a) {
    return torch::from_blob(const_cast<double*>(a.data()), {a.size()}, torch::kFloat64).clone();
  };
  BasisField& b = model_.basis[f];
  b.map_centers = tensor(m.centers), b.map_weights = tensor(m.weights);
  b.map_poly = tensor(m.poly), b.map_shift = vector(m.shift), b.map_scale = vector(m.scale);
  char line[200];
  std::snprintf(
      line, sizeof line,
      "coefficient map of %s: %lld training latents of %lld inputs%s, smoothing %.0e, "
      "error %.2f%% of the coefficients on the median run left out (%d folds)",
      kStageNames[f], static_cast<long long>(rows), static_cast<long long>(d),
      with_velocity ? (with_mu ? " (z, mu, latent velocity)" : " (z, latent velocity)") : "",
      m.smoothing, 100 * std::sqrt(report.cv_error), report.folds);
  say(line);
  return report.cv_error;
}

}  // namespace nsf::train
