// What the stages start from: the normalisation of a fresh model (moments over every training
// frame), or a base model's encoder, g and normalisation (--base-model); and the training frames'
// fields as the setup and the stages read them.
#include <algorithm>

#include "core/error.h"
#include "nn/train/trainer_state.h"

namespace nsf::train {

void Trainer::compute_statistics() {
  // Moments in double over every training particle of every frame: one pass over the data.
  std::vector<double> s[3], q[3], us(3, 0.0), uq(3, 0.0);
  for (int k = 0; k < 3; ++k) s[k].assign(kTargetDim[k], 0.0), q[k].assign(kTargetDim[k], 0.0);
  const std::vector<Vec3>& X = data_.rest_positions();
  for (size_t i = 0; i < store_.size(); ++i) {
    const std::vector<float>& x = frame_field(i, 0);
    for (size_t j = 0; j < x.size(); ++j) {
      const double u = double(x[j]) - X[j / 3][int(j % 3)];
      us[j % 3] += u, uq[j % 3] += u * u;
    }
    for (int k = 0; k < 3; ++k) {
      const int d = kTargetDim[k];
      const std::vector<float>& v = frame_field(i, k);
      for (size_t j = 0; j < v.size(); ++j) s[k][j % d] += v[j], q[k][j % d] += double(v[j]) * v[j];
    }
  }
  const double points = double(store_.size()) * data_.particle_count();
  model_.norm_x = Normalizer::from_moments(s[0], q[0], points);
  model_.norm_u = Normalizer::from_moments(us, uq, points);
  model_.rest =
      torch::from_blob(const_cast<double*>(X[0].data()), {int64_t(X.size()), 3}, torch::kFloat64)
          .to(torch::kFloat32);
  model_.norm_tau = Normalizer::from_moments(s[1], q[1], points);
  model_.norm_C = Normalizer::from_moments(s[2], q[2], points);

  std::vector<double> xs(3, 0.0), xq(3, 0.0);
  for (const Vec3& X : data_.rest_positions())
    for (int i = 0; i < 3; ++i) xs[i] += X[i], xq[i] += X[i] * X[i];
  model_.norm_X = Normalizer::from_moments(xs, xq, double(data_.particle_count()));

  // μ statistics over runs (not frames): each run is one parameter sample.
  std::vector<double> ms(1, 0.0), mq(1, 0.0);
  model_.mu_min = model_.mu_max = data_.train()[0].mu;
  model_.training_box = training_box(data_);
  for (const SimulationFile& r : data_.train()) {
    ms[0] += r.mu, mq[0] += r.mu * r.mu;
    model_.mu_min = std::min(model_.mu_min, r.mu), model_.mu_max = std::max(model_.mu_max, r.mu);
  }
  model_.norm_mu = Normalizer::from_moments(ms, mq, double(data_.train().size()));
}

void Trainer::start_from_base_model() {
  NeuralModel base = NeuralModel::load(opt_.base_model);
  base.check_scene(model_.scene, data_.dir());
  if (base.has_mu != model_.has_mu)
    fail(opt_.base_model, ": ", base.has_mu ? "conditioned" : "not conditioned",
         " on mu, the dataset ", base.has_mu ? "has none" : "has mu");
  // Fresh h and l of the base model's shape, from this run's seed; τ's and C's coefficients in
  // the kinds this run asks for (--coefficients), whatever the base model's were.
  base.config.coefficients = cfg_.net.coefficients;
  base.config.affine_uses_velocity = cfg_.net.affine_uses_velocity;
  base.config.stress_uses_velocity = cfg_.net.stress_uses_velocity;
  const NeuralModel fresh(base.config, base.scene, base.has_mu);
  base.h = fresh.h;
  base.l = fresh.l;
  base.basis[1].net = fresh.basis[1].net;
  base.basis[2].net = fresh.basis[2].net;
  model_ = std::move(base);
  stage_ = 1;
  // τ's and C's bases from this dataset; over a team process 0 fits them (share_setup).
  if (model_.is_basis() && team_rank() == 0) fit_bases(1);
}

const std::vector<float>& Trainer::frame_field(size_t i, int f) {
  if (f == 0 || !store_.positions_only()) {
    const FrameData& d = store_.get(i);
    return f == 0 ? d.x : f == 1 ? d.tau : d.C;
  }
  field_scratch_ =
      data_.read_field(data_.train()[store_.sim_of(i)], store_.frame_of(i), f == 1 ? "tau" : "C");
  return field_scratch_;
}

}  // namespace nsf::train
