// One optimiser step of the paper's coordinate networks (g with the encoder, then h, then l): a
// batch of frames, particles drawn within each, and the normalised MSE of the stage's field.
#include <algorithm>
#include <random>
#include <vector>

#include "nn/train/trainer_state.h"

namespace nsf::train {

double Trainer::train_step() {
  if (model_.is_basis()) return basis_step();
  const int64_t P = static_cast<int64_t>(data_.particle_count());
  const int64_t B = cfg_.frames_per_batch[stage_];
  const int64_t n = particles_per_batch_frame(stage_);
  const int d = kTargetDim[stage_];

  // Frames first, then particles within each frame (App. D's batches of whole frames do not fit
  // a CPU budget; this keeps a step's memory independent of the dataset size).
  // Stages 2 and 3 draw latent rows (one per frame: its encoder latent, refined).
  const size_t choices = stage_ == 0 ? store_.size() : latent_frame_.size();
  std::uniform_int_distribution<size_t> pick_frame(0, choices - 1);
  std::vector<int64_t> rows(B);
  std::uniform_int_distribution<int64_t> pick_particle(0, P - 1);
  std::vector<int64_t> frames(B), particles(B * n);
  torch::Tensor target = torch::empty({B * n, d});
  torch::Tensor full_x = stage_ == 0 ? torch::empty({B, P, 3}) : torch::Tensor();
  float* t = target.data_ptr<float>();
  // Over a team every process draws the whole global batch, and fills the entries whose frames
  // it holds (mine, and their points: keep).
  std::vector<int64_t> mine, keep;
  for (int64_t b = 0; b < B; ++b) {
    rows[b] = static_cast<int64_t>(pick_frame(rng_));
    frames[b] = stage_ == 0 ? rows[b] : latent_frame_[size_t(rows[b])];
    const bool held = store_.holds(size_t(frames[b]));
    if (held) {
      mine.push_back(b);
      for (int64_t j = 0; j < n; ++j) keep.push_back(b * n + j);
    }
    const FrameData* f = held ? &store_.get(frames[b]) : nullptr;
    if (stage_ == 0 && held) std::copy(f->x.begin(), f->x.end(), full_x[b].data_ptr<float>());
    const std::vector<float>* src = !held ? nullptr : &frame_field(size_t(frames[b]), stage_);
    for (int64_t j = 0; j < n; ++j) {
      const int64_t p = n == P ? j : pick_particle(rng_);
      particles[b * n + j] = p;
      if (!held) continue;
      std::copy(&(*src)[d * p], &(*src)[d * p] + d, t + (b * n + j) * d);
    }
  }
  const torch::Tensor pidx = torch::tensor(particles, torch::kInt64);
  const torch::Tensor fidx = torch::tensor(frames, torch::kInt64).repeat_interleave(n);
  const torch::Tensor ridx = torch::tensor(rows, torch::kInt64).repeat_interleave(n);
  // The noise of the whole global batch, so that every process's generator moves alike.
  const torch::Tensor z_all = stage_ == 0 ? torch::Tensor() : noisy(latents_.index_select(0, ridx));
  adam_->zero_grad();
  double loss_value = 0;
  if (!keep.empty()) {
    const torch::Tensor Xn = entries(Xn_.index_select(0, pidx), keep).to(dev_);
    target = entries(target, keep).to(dev_);
    torch::Tensor pred, goal;
    if (stage_ == 0) {
      const torch::Tensor z = model_.encode(entries(full_x, mine).to(dev_)).repeat_interleave(n, 0);
      pred = model_.g->forward(model_.g_input(Xn, z));
      goal = model_.displacement ? model_.norm_u.apply(target - model_.norm_X.invert(Xn))
                                 : model_.norm_x.apply(target);
    } else if (stage_ == 1) {
      const torch::Tensor mu = entries(mu_.index_select(0, fidx), keep).to(dev_);
      pred = model_.h->forward(model_.h_input(Xn, entries(z_all, keep), mu));
      goal = model_.norm_tau.apply(target);
    } else {
      pred = model_.l->forward(model_.l_input(Xn, entries(z_all, keep)));
      goal = model_.norm_C.apply(target);
    }
    // Over a team, each process's share of the global batch's mean.
    const torch::Tensor loss =
        team_ ? torch::mse_loss(pred, goal, torch::Reduction::Sum) / double(B * n * d)
              : torch::mse_loss(pred, goal);
    loss.backward();
    loss_value = loss.item<double>();
  }
  loss_value = sum_over_team(loss_value);
  adam_->step();
  return loss_value;
}

// Latent rows (CPU) for the decoders on dev_, with the noise of --latent-noise.
torch::Tensor Trainer::noisy(const torch::Tensor& z) {
  if (cfg_.latent_noise <= 0) return z.to(dev_);
  // From the trainer's own seeded generator, so that a resumed run draws the same noise.
  std::normal_distribution<float> normal(0.0f, float(cfg_.latent_noise));
  torch::Tensor e = torch::empty_like(z);
  float* p = e.data_ptr<float>();
  for (int64_t i = 0; i < e.numel(); ++i) p[i] = normal(rng_);
  return (z + e * model_.norm_z.std.cpu()).to(dev_);
}

}  // namespace nsf::train
