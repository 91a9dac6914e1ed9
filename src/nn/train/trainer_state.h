#pragma once
// The trainer behind nn/train/trainer.h: one class, whose parts live in the files of nn/train/,
// one job each: the stage loop (trainer.cpp), the normalisation or the base model a run starts
// from (setup.cpp), the MLP stages' step (mlp_stages.cpp), the bases and the basis stages' step
// (basis_stages.cpp), the coefficient maps (coefficient_map_fit.cpp), the latents of stages 2 and
// 3 (training_latents.cpp), a team of processes (team.cpp), the checkpoint (checkpoint.cpp) and
// the loss curves (loss_curves.cpp). For those files alone; the rest of nsf calls train_model.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "nn/config.h"
#include "nn/dataset.h"
#include "nn/model/neural_model.h"
#include "nn/train/gradient_team.h"
#include "nn/train/trainer.h"

#include <torch/optim/adam.h>

namespace nsf::train {

struct LossRow {
  int stage;
  long step;
  double loss, lr;
};

// Sizes of the decoder targets per stage: x (3), τ (6), C (9).
constexpr int kTargetDim[kStageCount] = {3, 6, 9};
constexpr const char* kNetworkNames[kStageCount] = {"g", "h", "l"};
// Latent rows per optimiser step of a basis model's stages 2 and 3: a row is one frame's whole
// field, and a small scene has a few hundred frames.
constexpr int64_t kBasisRows = 256;

class Trainer {
 public:
  Trainer(const std::string& data_dir, const std::string& out, const TrainOptions& o);

  // run_stages, and after a failure on the input (not while writing a file), the checkpoint it
  // wrote removed: resuming would fail the same way.
  TrainReport run();

 private:
  TrainReport run_stages();
  // Particles drawn per batch frame (at most all of them), and points per optimiser step.
  int64_t particles_per_batch_frame(int s) const {
    return std::min<int64_t>(int64_t(data_.particle_count()), cfg_.particles_per_frame[s]);
  }
  int64_t points_per_step(int s) const {
    if (model_.is_basis())  // each row is a whole frame's field
      return (s == 0 ? cfg_.frames_per_batch[0] : kBasisRows) * int64_t(data_.particle_count());
    return cfg_.frames_per_batch[s] * particles_per_batch_frame(s);
  }
  void say(const std::string& s) const {
    if (!cfg_.quiet && team_rank() == 0) std::fprintf(stderr, "%s\n", s.c_str());
  }
  int team_rank() const { return team_ ? team_->rank() : 0; }
  int team_size() const { return team_ ? team_->size() : 1; }
  // Rows `rows` of t over a team (the entries this process computes); all of t alone.
  torch::Tensor entries(const torch::Tensor& t, const std::vector<int64_t>& rows) const;
  // Over a team: the gradients and `loss` summed over the processes (the gradients in place).
  double sum_over_team(double loss);
  // Over a team: process 0's model, basis targets and resume decision to every process.
  void share_setup();
  std::string config_key() const;
  void compute_statistics();
  void compute_latents();
  void refine_latents();
  void store_trajectories();
  void start_from_base_model();
  torch::Tensor noisy(const torch::Tensor& z);
  void start_stage();
  std::vector<torch::Tensor> stage_parameters();
  double train_step();
  void fit_bases(int first_field);
  // A model with coefficient maps: stage_'s map through the training latents (nn/rbf_map.h),
  // returning its cross-validated error.
  double fit_coefficient_map();
  // Field f (x, τ, C) of training frame i: from the store, or, where it holds positions only,
  // from the run file. Valid until the next call.
  const std::vector<float>& frame_field(size_t i, int f);
  double basis_step();
  void save_checkpoint() const;
  // How many times checkpoint_every apart checkpoints are: one per 64 MiB of per-point bases, so
  // that a paper-size basis model (cake_paper: 840 MB, 12 s a write, against 55 ms a step) does
  // not spend its training writing checkpoints. 1 for the networks.
  long checkpoint_spacing() const;
  void load_checkpoint();
  void write_loss_curves(TrainReport& report) const;

  // Set while a file is written: a failure then (a full disk) is not one of the input.
  mutable bool writing_ = false;
  TrainOptions opt_;
  TrainConfig cfg_;
  std::string out_, ckpt_;
  torch::Device dev_;   // where the networks and the batches' tensors live (model_ too, in run())
  GradientTeam* team_;  // null for a single process
  Dataset data_;
  FrameStore store_;
  NeuralModel model_;
  torch::Tensor Xn_;                   // |P| × 3 normalised rest positions
  torch::Tensor latents_;              // rows × r: ẑ_n = e(xⁿ) per frame once stage 1 is done
  std::vector<int64_t> latent_frame_;  // the training frame of each row of latents_
  torch::Tensor mu_;                   // frames × 1 (physical μ of each training frame's run)
  std::vector<float> field_scratch_;   // frame_field's τ or C read from a file
  std::mt19937_64 rng_;
  int stage_ = 0;
  long step_ = 0;
  std::vector<LossRow> history_;
  std::unique_ptr<torch::optim::Adam> adam_;
  // Basis models: each training frame's projection onto each field's basis (frames × K), the
  // targets of the coefficient networks.
  torch::Tensor targets_[kStageCount];
};

}  // namespace nsf::train
