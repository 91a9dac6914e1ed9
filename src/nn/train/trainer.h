#pragma once
// `nsf train`: the three training stages of §4.5 — (1) encoder e and deformation decoder g on
// positions, (2) stress decoder h and (3) affine decoder l on the frozen latents ẑ_n = e(xⁿ).
// Torch-free interface; the stage loop lives in trainer.cpp, the stages' parts beside it in
// nn/train/ (trainer_state.h lists them).
#include <array>
#include <string>
#include <vector>

#include "data/training_box.h"
#include "nn/config.h"
#include "nn/train/gradient_team.h"

namespace nsf {

struct TrainOptions {
  TrainConfig config;
  bool resume = false;  // continue from "<out>.ckpt" when it exists
  // Without resume, a checkpoint "<out>.ckpt" left by an interrupted run is refused (it may hold
  // hours of training); fresh deletes it and starts over.
  bool fresh = false;
  // Train on a dataset an interrupted sweep left incomplete (nn/dataset.h), instead of refusing.
  bool allow_incomplete = false;
  // Stop (as if killed) after this many optimiser steps in this process; < 0 = never. For tests
  // and time-boxed runs: a later --resume continues from the last checkpoint.
  long stop_after = -1;
  // Epochs per stage (one epoch = every particle of every training frame once); a stage with a
  // value > 0 gets ceil(epochs · frames · |P| / points per step) steps instead of config.steps.
  std::array<double, kStageCount> epochs = {-1, -1, -1};
  // Start from this model: keep its encoder, g and normalisation, skip stage 1 and train h and l
  // afresh (empty = train all three stages).
  std::string base_model;
  // Where the networks train: "cpu", or "cuda" / "cuda:N" with a LibTorch built with CUDA
  // (docs/TRAINING.md, "Training on a GPU"). Batches are drawn and assembled on the CPU either
  // way, with the same random numbers; the model file and the checkpoint hold CPU tensors.
  std::string device = "cpu";
  // Several processes training together (`mpirun -np K nsf train`; nn/train/gradient_team.h): each
  // holds its share of the frames, computes its share of every global batch of
  // frames_per_batch frames, and the gradients are summed; process 0 writes the checkpoints,
  // the model and the loss curves. Null: this process alone.
  GradientTeam* team = nullptr;
};

struct StageReport {
  long steps = 0;  // optimiser steps taken in this process
  double seconds = 0;
  double points_per_second = 0;  // decoder training points (particle samples) per second
  double frames_per_second = 0;  // stage 1 only: full frames through the encoder per second
  double final_loss = 0;         // mean normalised MSE over the stage's last steps
};

struct TrainReport {
  std::array<StageReport, kStageCount> stages;
  std::string model_path, checkpoint_path, loss_csv, loss_png;  // png empty without gnuplot
  bool completed = false;  // false when stop_after ended the run early
  TrainingBox box;         // what the model records of its training runs (data/training_box.h)
};

TrainReport train_model(const std::string& data_dir, const std::string& out_path,
                        const TrainOptions& options);

// Throws nsf::Error naming the problem unless `device` (TrainOptions::device) can train here:
// "cpu" always; "cuda[:N]" with a LibTorch built with CUDA and that device visible.
void check_training_device(const std::string& device);

// Where train_model keeps its checkpoint and loss curves for a model path.
std::string checkpoint_path_for(const std::string& model_path);
std::string loss_csv_path_for(const std::string& model_path);

}  // namespace nsf
