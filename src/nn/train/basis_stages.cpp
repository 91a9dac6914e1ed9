// A basis model's stages: each field's per-point basis from the training frames (the snapshot
// SVD of nn/train/basis_fit.h), and one optimiser step of a coefficient network against the
// frames' projections.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/timer.h"
#include "nn/train/basis_fit.h"
#include "nn/train/trainer_state.h"

namespace nsf::train {

namespace {

// τ's Frobenius norm counts its off-diagonal entries twice (xx yy zz xy yz xz).
const std::vector<double> kBasisWeights[kStageCount] = {
    {1, 1, 1}, {1, 1, 1, M_SQRT2, M_SQRT2, M_SQRT2}, std::vector<double>(9, 1.0)};

}  // namespace

void Trainer::fit_bases(int first_field) {
  const int64_t P = int64_t(data_.particle_count());
  const std::vector<Vec3>& X = data_.rest_positions();
  const double gib = 1024.0 * 1024.0 * 1024.0;
  // The model's shapes, not this run's flags: with --base-model they are the base's.
  for (int f = first_field; f < kStageCount; ++f) {
    const int d = kTargetDim[f];
    const double start = now_seconds();
    // The frames × columns matrix of a field takes what the memory budget leaves beside the
    // cached frames and the field's modes (held twice for a moment: the fit's and the model's),
    // at least 256 MiB; a larger one goes through in slices (nn/train/basis_fit.h).
    const double modes_gib = 2.0 * double(P * d) * model_.config.modes[f] * sizeof(float) / gib;
    const size_t cap =
        size_t(std::max(0.25, store_.budget_gib() - store_.cached_gib() - modes_gib) * gib);
    const SnapshotBasis b = fit_snapshot_basis(
        store_.size(), size_t(P * d),
        [&](size_t i, float* row) {
          const std::vector<float>& v = frame_field(i, f);
          if (f == 0)
            for (int64_t j = 0; j < 3 * P; ++j) row[j] = float(double(v[j]) - X[j / 3][j % 3]);
          else
            std::copy_n(v.data(), P * d, row);
        },
        kBasisWeights[f], model_.config.modes[f], cap);
    const int64_t K = b.sigma.size();
    if (K != model_.config.modes[f]) {
      say("basis of " + std::string(kStageNames[f]) + ": " + std::to_string(K) +
          " modes (the training frames' rank), not " + std::to_string(model_.config.modes[f]));
      model_.config.modes[f] = int(K);
      const int64_t in = model_.basis[f].net->in_features();
      model_.basis[f].net =
          FieldMlp(in, K, model_.config.coefficient_width, model_.config.coefficient_depth);
    }
    BasisField& field = model_.basis[f];
    field.mean = torch::from_blob(const_cast<float*>(b.mean.data()), {P, d}).clone();
    // Eigen's column-major columns × K is, per point, dim × K with a stride: copy to row-major.
    field.modes = torch::from_blob(const_cast<float*>(b.modes.data()), {K, P, d})
                      .permute({1, 2, 0})
                      .contiguous();
    targets_[f] = torch::from_blob(const_cast<float*>(b.coeffs.data()), {K, int64_t(store_.size())})
                      .t()
                      .contiguous();
    const Eigen::VectorXf spread = (b.sigma / std::sqrt(double(store_.size()))).cast<float>();
    field.scale = torch::from_blob(const_cast<float*>(spread.data()), {K}).clone();
    char line[160];
    std::snprintf(line, sizeof line,
                  "basis of %s: %lld modes hold %.2f%% of the training frames' variance (%.1f s)",
                  kStageNames[f], static_cast<long long>(K), 100 * (1 - b.residual_share()),
                  now_seconds() - start);
    say(line);
  }
}

// One step of a basis model's stage: the coefficient network against each row's projection.
// The loss is the field's squared error over its variance per frame, as the MLP stages' is
// per component: the modes are orthonormal, so coefficient error is field error.
double Trainer::basis_step() {
  const int64_t P = int64_t(data_.particle_count());
  const torch::Tensor& targets = targets_[stage_];
  const int64_t B = stage_ == 0 ? cfg_.frames_per_batch[0] : kBasisRows;
  const size_t choices = stage_ == 0 ? store_.size() : latent_frame_.size();
  std::uniform_int_distribution<size_t> pick(0, choices - 1);
  std::vector<int64_t> rows(B), frames(B);
  for (int64_t b = 0; b < B; ++b) {
    rows[b] = int64_t(pick(rng_));
    frames[b] = stage_ == 0 ? rows[b] : latent_frame_[size_t(rows[b])];
  }
  // This process's entries: in stage 1 those whose frame it holds, in stages 2 and 3 (latent
  // rows, no frame data) every size-th.
  std::vector<int64_t> mine;
  for (int64_t b = 0; b < B; ++b)
    if (stage_ == 0 ? store_.holds(size_t(frames[b])) : b % team_size() == team_rank())
      mine.push_back(b);
  torch::Tensor goal = targets.index_select(0, torch::tensor(frames, torch::kInt64));  // CPU
  torch::Tensor pred;
  if (stage_ == 0) {
    torch::Tensor full_x = torch::empty({B, P, 3});
    for (int64_t b = 0; b < B; ++b) {
      const bool held = store_.holds(size_t(frames[b]));
      if (held) {
        const FrameData& f = store_.get(size_t(frames[b]));
        std::copy(f.x.begin(), f.x.end(), full_x[b].data_ptr<float>());
      }
    }
    if (!mine.empty())
      pred = model_.coefficients(0, model_.encode(entries(full_x, mine).to(dev_)), torch::Tensor());
  } else {
    const torch::Tensor z = noisy(latents_.index_select(0, torch::tensor(rows, torch::kInt64)));
    const torch::Tensor mu = mu_.index_select(0, torch::tensor(frames, torch::kInt64));
    if (!mine.empty())
      pred = model_.coefficients(stage_, entries(z, mine), entries(mu, mine).to(dev_));
  }
  const double variance = targets.pow(2).sum(1).mean().item<double>();
  adam_->zero_grad();
  double loss = 0;
  if (!mine.empty()) {
    const torch::Tensor error = (pred - entries(goal, mine).to(dev_)).pow(2).sum(1);
    // Over a team, each process's share of the global batch's mean.
    const torch::Tensor l = (team_ ? error.sum() / double(B) : error.mean()) / variance;
    l.backward();
    loss = l.item<double>();
  }
  loss = sum_over_team(loss);
  adam_->step();
  return loss;
}

}  // namespace nsf::train
