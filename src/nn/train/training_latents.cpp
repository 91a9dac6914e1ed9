// The latents stages 2 and 3 learn from: each training frame's encoder latent, refined by
// Gauss–Newton on positions as the ROM finds them (--refine-latents), and kept in the model run
// by run for the ROM's latent prior.
#include <algorithm>
#include <limits>

#include "core/blas_threads.h"
#include "core/progress.h"
#include "nn/network_samples.h"
#include "nn/train/trainer_state.h"

namespace nsf::train {

void Trainer::compute_latents() {
  const int64_t P = static_cast<int64_t>(data_.particle_count());
  const int64_t n = static_cast<int64_t>(store_.size());
  // Over a team each process encodes (and refines) the frames it holds; the sum gives everyone
  // every row, as a row is zero on every other process.
  latents_ = torch::zeros({n, model_.latent_dim()});
  {
    torch::NoGradGuard no_grad;
    for (int64_t i = 0; i < n; ++i) {
      if (!store_.holds(size_t(i))) continue;
      const FrameData& f = store_.get(i);
      const torch::Tensor x = torch::from_blob(const_cast<float*>(f.x.data()), {1, P, 3});
      latents_[i] = model_.encode(x.to(dev_))[0].cpu();
    }
  }
  if (cfg_.refine_latents > 0) refine_latents();  // needs autodiff for its Jacobians
  if (team_) team_->sum(latents_.data_ptr<float>(), size_t(latents_.numel()));
  std::vector<double> s(model_.latent_dim(), 0.0), q(model_.latent_dim(), 0.0);
  auto acc = latents_.accessor<float, 2>();
  for (int64_t i = 0; i < n; ++i)
    for (int64_t j = 0; j < model_.latent_dim(); ++j)
      s[j] += acc[i][j], q[j] += acc[i][j] * acc[i][j];
  model_.norm_z = Normalizer::from_moments(s, q, double(n));
  model_.to(dev_);  // the new norm_z (the rest is there already)
  latent_frame_.resize(size_t(n));
  for (int64_t i = 0; i < n; ++i) latent_frame_[size_t(i)] = i;
}

void Trainer::refine_latents() {
  // The ROM finds ẑ by Gauss–Newton on positions, and that latent differs from the encoder's in
  // directions g barely sees but h and l (trained on encoder latents only) answer wildly:
  // measured with `nsf eval --refine`. Training h and l on refined latents removes the mismatch.
  // On the CPU, as the ROM runs it; the model comes back to dev_ at the end.
  model_.to(torch::kCPU);
  const FrameLatentRefiner refiner(model_, data_.rest_positions(), cfg_.refine_latents);
  // As many frames at a time as refine_many runs in parallel: streamed frames must be copied out.
  const size_t batch = size_t(std::max(1, blas_thread_count()));
  std::vector<int64_t> own;  // the frames this process holds (all of them, alone)
  for (size_t i = 0; i < store_.size(); ++i)
    if (store_.holds(i)) own.push_back(int64_t(i));
  const size_t frames = own.size();
  std::vector<std::vector<float>> x(batch);
  Progress progress("refining latents", long(frames), "frames");
  for (size_t first = 0; first < frames; first += batch) {
    const size_t count = std::min(batch, frames - first);
    std::vector<const float*> xs(count);
    std::vector<Eigen::VectorXd> z(count);
    for (size_t k = 0; k < count; ++k) {
      const int64_t i = own[first + k];
      x[k] = store_.get(size_t(i)).x;  // a copy: streamed frames share one buffer
      xs[k] = x[k].data();
      const torch::Tensor z0 = latents_[i].to(torch::kFloat64).contiguous();
      z[k] = Eigen::Map<const Eigen::VectorXd>(z0.data_ptr<double>(), z0.size(0));
    }
    refiner.refine_many(xs, z);
    for (size_t k = 0; k < count; ++k)
      latents_[own[first + k]] =
          torch::from_blob(z[k].data(), {z[k].size()}, torch::kFloat64).to(torch::kFloat32);
    if (!cfg_.quiet) progress.update(long(first + count));
  }
  if (!cfg_.quiet) progress.finish();
  model_.to(dev_);
}

void Trainer::store_trajectories() {
  // The model keeps the latents h and l learnt from, run by run, for the ROM's latent prior.
  size_t frames = std::numeric_limits<size_t>::max();
  for (size_t s = 0; s < data_.train().size(); ++s) {
    size_t k = 0;
    while (store_.index_of(s, k) != FrameStore::kNone) ++k;
    frames = std::min(frames, k);
  }
  const int64_t runs = int64_t(data_.train().size());
  std::vector<int64_t> rows;  // of latents_, run by run
  std::vector<float> mu;
  for (size_t s = 0; s < data_.train().size(); ++s) {
    mu.push_back(float(data_.train()[s].mu));
    for (size_t k = 0; k < frames; ++k) rows.push_back(int64_t(store_.index_of(s, k)));
  }
  model_.trajectory_latents = latents_.index_select(0, torch::tensor(rows))
                                  .reshape({runs, int64_t(frames), model_.latent_dim()});
  model_.trajectory_mu = torch::tensor(mu);
}

}  // namespace nsf::train
