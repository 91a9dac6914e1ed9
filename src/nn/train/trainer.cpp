#include "nn/train/trainer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "core/memory.h"
#include "core/progress.h"
#include "core/timer.h"
#include "nn/torch_settings.h"
#include "nn/train/batch_budget.h"
#include "nn/train/trainer_state.h"

#include <torch/cuda.h>

namespace nsf {

namespace fs = std::filesystem;

namespace {

// ≤ 0: half of what the machine has available now, at least 2 GiB (the former fixed default).
double memory_budget_gib(double requested) {
  if (requested > 0) return requested;
  return std::max(2.0, 0.5 * available_memory_mib() / 1024.0);
}

// The device of --device, checked before any data is read.
torch::Device training_device(const std::string& name) {
  std::optional<torch::Device> d;
  try {
    d.emplace(name);
  } catch (const c10::Error&) {
    fail("--device ", name, ": not a device (cpu, cuda or cuda:N)");
  }
  if (d->is_cpu()) return *d;
  if (!d->is_cuda()) fail("--device ", name, ": nsf trains on cpu or cuda");
  if (!torch::cuda::is_available())
    fail("--device ", name,
         ": this nsf was built with a LibTorch without CUDA, or no CUDA device is visible "
         "(Debian's LibTorch is CPU-only; docs/TRAINING.md, \"Training on a GPU\", says how to "
         "build with one)");
  const int64_t count = int64_t(torch::cuda::device_count());
  if (d->has_index() && d->index() >= count)
    fail("--device ", name, ": there are ", count, " CUDA device(s), numbered from 0");
  return *d;
}

// The memory budget, once the batches are checked against it and the dataset: before the frames
// are read, and before a batch is allocated (nn/train/batch_budget.h).
double checked_budget(const Dataset& data, const TrainConfig& c) {
  size_t frames = 0;
  for (const SimulationFile& r : data.train()) frames += r.frames;
  const double budget = memory_budget_gib(c.memory_budget_gib);
  check_batch_sizes(c, frames, data.particle_count(), budget);
  if (!c.quiet && c.net.decoder != DecoderFamily::basis)
    for (int s = 0; s < kStageCount; ++s)
      if (size_t(c.particles_per_frame[s]) > data.particle_count())
        std::fprintf(stderr,
                     "note: --particles-per-frame %d (stage %d) is more than the dataset's %zu "
                     "particles: each batch frame uses all of them\n",
                     c.particles_per_frame[s], s + 1, data.particle_count());
  return budget;
}

}  // namespace

namespace train {

Trainer::Trainer(const std::string& data_dir, const std::string& out, const TrainOptions& o)
    : opt_(o),
      cfg_(o.config),
      out_(out),
      ckpt_(checkpoint_path_for(out)),
      dev_(training_device(o.device)),
      team_(o.team),
      data_(data_dir, o.allow_incomplete),
      // x alone for a fresh basis model; with a base model the family is the base's, and the
      // store keeps every field as before.
      store_(data_, checked_budget(data_, cfg_), team_rank(), team_size(),
             cfg_.net.decoder == DecoderFamily::basis && o.base_model.empty()),
      model_(cfg_.net, SceneFingerprint::of(data_.scene_name(), data_.rest_positions()),
             data_.has_mu()),
      rng_(cfg_.seed) {
  for (int s = 0; s < kStageCount; ++s) {
    if (o.epochs[s] <= 0) continue;
    const double points = double(store_.size()) * double(data_.particle_count());
    cfg_.steps[s] =
        std::max(1L, long(std::ceil(o.epochs[s] * points / double(points_per_step(s)))));
  }
}

TrainReport Trainer::run() {
  std::error_code ec;
  const bool checkpoint_before = fs::exists(ckpt_, ec);
  try {
    return run_stages();
  } catch (const Error&) {
    // A run that failed on its input (a dataset too small for a coefficient map, a loss that
    // diverged) fails the same way when resumed: the checkpoint it wrote would only make its
    // retry refuse "an interrupted training run". One that failed writing a file (a full disk)
    // keeps it for --resume, as does a run resumed from it, and one a signal ends (its process
    // dies of the signal, and never gets here).
    if (!writing_ && !checkpoint_before && team_rank() == 0) fs::remove(ckpt_, ec);
    throw;
  }
}

TrainReport Trainer::run_stages() {
  TrainReport report;
  report.model_path = out_;
  report.checkpoint_path = ckpt_;
  bool resumed = opt_.resume && fs::exists(ckpt_);
  if (team_) {  // process 0's view of the (shared) folder decides; every process loads the file
    std::string yes = resumed ? "1" : "0";
    team_->broadcast(yes);
    resumed = yes == "1";
  }
  if (opt_.resume && !resumed) say("no checkpoint " + ckpt_ + " yet: starting from scratch");
  if (resumed) {
    load_checkpoint();
    say("resuming from " + ckpt_ + ": stage " + std::to_string(stage_ + 1) + ", step " +
        std::to_string(step_));
  } else if (!opt_.base_model.empty()) {
    start_from_base_model();
    share_setup();
    model_.to(dev_);
    start_stage();
    say("stage 1 skipped: encoder and g from " + opt_.base_model);
  } else {
    // Over a team, process 0 makes the one-time statistics and bases (reading the frames it does
    // not hold from their files) and sends them to the others: bit for bit the same everywhere.
    if (team_rank() == 0) {
      compute_statistics();
      if (model_.is_basis()) fit_bases(0);
    }
    share_setup();
    model_.to(dev_);
    start_stage();
  }
  // On the CPU, as the batches are drawn there (model_ is on dev_ by now).
  Xn_ = model_.norm_X
            .apply(torch::from_blob(const_cast<double*>(data_.rest_positions()[0].data()),
                                    {int64_t(data_.particle_count()), 3}, torch::kFloat64)
                       .to(dev_, torch::kFloat32))
            .cpu();
  std::vector<float> mu;
  for (size_t i = 0; i < store_.size(); ++i)
    mu.push_back(float(data_.train()[store_.sim_of(i)].mu));
  mu_ = torch::tensor(mu).reshape({-1, 1});

  long steps_this_process = 0;
  for (; stage_ < kStageCount; ++stage_, step_ = 0) {
    if (stage_ > 0 && !latents_.defined()) compute_latents();
    // A coefficient map is fitted, not trained: no optimiser steps.
    const bool mapped = model_.config.uses_map(stage_);
    const long total = mapped ? 0 : cfg_.steps[stage_];
    const long spacing = checkpoint_spacing();  // the bases are fitted by now
    const int64_t points_per_step = this->points_per_step(stage_);
    std::unique_ptr<Progress> bar;
    if (!cfg_.quiet && !mapped)
      bar = std::make_unique<Progress>(
          std::string("stage ") + std::to_string(stage_ + 1) + "/3 " + kStageNames[stage_], total,
          "steps");
    StageReport& rep = report.stages[stage_];
    const long first = step_;
    const double start = now_seconds();
    const double map_error = mapped ? fit_coefficient_map() : 0;
    double ema = -1;
    for (; step_ < total; ++step_) {
      if (opt_.stop_after >= 0 && steps_this_process >= opt_.stop_after) return report;
      const double lr = learning_rate(step_, total);
      for (auto& group : adam_->param_groups())
        static_cast<torch::optim::AdamOptions&>(group.options()).lr(lr);
      const double loss = train_step();
      if (!std::isfinite(loss))
        fail("training diverged in stage ", stage_ + 1, " (", kStageNames[stage_], ") at step ",
             step_, ": loss ", loss);
      history_.push_back({stage_, step_, loss, lr});
      ++steps_this_process;
      ema = ema < 0 ? loss : 0.98 * ema + 0.02 * loss;
      const double secs = now_seconds() - start;
      if (bar) {
        char extra[96];
        std::snprintf(extra, sizeof extra, "loss %.3e lr %.0e %s pts/s", ema, lr,
                      Progress::format_rate(double(step_ + 1 - first) * points_per_step /
                                            std::max(secs, 1e-9))
                          .c_str());
        bar->update(step_ + 1, extra);
      }
      if (cfg_.checkpoint_every > 0 && (step_ + 1) % (cfg_.checkpoint_every * spacing) == 0 &&
          step_ + 1 < total) {
        ++step_;  // the checkpoint resumes *after* this step
        save_checkpoint();
        --step_;
      }
    }
    rep.steps = total - first;
    rep.seconds = now_seconds() - start;
    model_.train_seconds += rep.seconds;
    // A base model's attachments (the ROM's calibration, say) described other fields.
    model_.attachments.clear();
    rep.points_per_second = rep.steps * double(points_per_step) / std::max(rep.seconds, 1e-9);
    if (stage_ == 0)
      rep.frames_per_second =
          rep.steps * double(cfg_.frames_per_batch[0]) / std::max(rep.seconds, 1e-9);
    const long tail = std::max<long>(1, total / 20);
    double sum = 0;
    long count = 0;
    for (auto it = history_.rbegin(); it != history_.rend() && count < tail; ++it)
      if (it->stage == stage_) sum += it->loss, ++count;
    rep.final_loss = mapped ? map_error : count ? sum / count : 0;
    if (bar) bar->finish();
    std::ostringstream os;
    os << "stage " << stage_ + 1 << " (" << kStageNames[stage_] << "): ";
    if (mapped)
      os << "coefficient map fitted in " << Progress::format_seconds(rep.seconds);
    else
      os << rep.steps << " steps in " << Progress::format_seconds(rep.seconds) << ", "
         << Progress::format_rate(rep.points_per_second) << " points/s through "
         << kNetworkNames[stage_];
    if (stage_ == 0)
      os << " (+ " << Progress::format_rate(rep.frames_per_second) << " frames/s encoded)";
    os << ", final loss " << rep.final_loss;
    say(os.str());
    // The next stage trains on latents of the finished encoder: compute them before the
    // checkpoint so that a resumed run reuses the exact same numbers.
    if (stage_ == 0) compute_latents();
    if (stage_ + 1 < kStageCount) {
      const int next = stage_ + 1;
      ++stage_, step_ = 0;
      start_stage();
      save_checkpoint();
      stage_ = next - 1;
    }
  }
  report.completed = true;
  report.box = model_.training_box;
  if (team_rank() != 0) return report;  // process 0 writes the model and the loss curves
  model_.to(torch::kCPU);
  if (latents_.defined()) store_trajectories();
  writing_ = true;
  model_.save(out_);
  write_loss_curves(report);
  writing_ = false;
  fs::remove(ckpt_);
  return report;
}

std::vector<torch::Tensor> Trainer::stage_parameters() {
  if (model_.is_basis()) {
    auto p = model_.basis[stage_].net->parameters();
    if (stage_ == 0 && model_.config.encoder == "network")
      for (auto& t : model_.encoder->parameters()) p.insert(p.begin(), t);
    return p;
  }
  if (stage_ == 0) {
    auto p = model_.encoder->parameters();
    for (auto& t : model_.g->parameters()) p.push_back(t);
    return p;
  }
  return stage_ == 1 ? model_.h->parameters() : model_.l->parameters();
}

void Trainer::start_stage() {
  adam_ = std::make_unique<torch::optim::Adam>(stage_parameters(),
                                               torch::optim::AdamOptions(kLearningRates[0]));
}

}  // namespace train

void check_training_device(const std::string& device) {
  training_device(device);
}

TrainReport train_model(const std::string& data_dir, const std::string& out_path,
                        const TrainOptions& options) {
  const std::string ckpt = checkpoint_path_for(out_path);
  if (options.resume && options.fresh) fail("--resume and --fresh exclude each other");
  const bool lead = !options.team || options.team->rank() == 0;  // the one that writes files
  if (!options.resume && fs::exists(ckpt)) {
    if (!options.fresh)
      fail(ckpt, " holds the checkpoint of an interrupted training run of ", out_path,
           ": continue it with --resume, or give --fresh to delete it and start over");
    if (!options.config.quiet && lead)
      std::fprintf(stderr, "--fresh: deleting the checkpoint %s and starting over\n", ckpt.c_str());
    if (lead) fs::remove(ckpt);
  }
  if (fs::path(out_path).has_parent_path())
    fs::create_directories(fs::path(out_path).parent_path());
  seed_torch(options.config.seed);
  train::Trainer t(data_dir, out_path, options);
  return t.run();
}

}  // namespace nsf
