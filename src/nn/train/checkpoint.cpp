// The checkpoint "<out>.ckpt": the model, the stage and step, the random generator, the
// optimiser, the latents and basis targets and the loss history, written every checkpoint_every
// steps and at each stage's end, for --resume; and the settings key that refuses a checkpoint
// written with other settings.
#include <algorithm>
#include <array>
#include <sstream>
#include <string>

#include "core/error.h"
#include "nn/checked_archive.h"
#include "nn/train/trainer_state.h"

namespace nsf {

std::string checkpoint_path_for(const std::string& model_path) {
  return model_path + ".ckpt";
}

namespace train {

namespace {

// After an optimiser's state is loaded from a checkpoint (CPU tensors), onto its parameters'
// device.
void move_adam_state(torch::optim::Adam& adam, const torch::Device& device) {
  for (auto& entry : adam.state()) {
    auto& s = static_cast<torch::optim::AdamParamState&>(*entry.second);
    s.exp_avg(s.exp_avg().to(device));
    s.exp_avg_sq(s.exp_avg_sq().to(device));
    if (s.max_exp_avg_sq().defined()) s.max_exp_avg_sq(s.max_exp_avg_sq().to(device));
  }
}

}  // namespace

std::string Trainer::config_key() const {
  const NetConfig& n = cfg_.net;
  std::ostringstream os;
  os << model_.scene.describe() << " r=" << n.latent_dim << " depth=" << n.depth
     << " widths=" << n.width_g << "," << n.width_h << "," << n.width_l
     << " enc=" << n.encoder_hidden << " mu=" << n.stress_uses_mu << " steps=" << cfg_.steps[0]
     << "," << cfg_.steps[1] << "," << cfg_.steps[2] << " batch=" << cfg_.frames_per_batch[0] << ","
     << cfg_.frames_per_batch[1] << "," << cfg_.frames_per_batch[2] << "x"
     << cfg_.particles_per_frame[0];
  // One figure when the stages agree: the form checkpoints had before it could differ by stage.
  const std::array<int, kStageCount>& ppf = cfg_.particles_per_frame;
  if (ppf[1] != ppf[0] || ppf[2] != ppf[0]) os << "," << ppf[1] << "," << ppf[2];
  os << " seed=" << cfg_.seed << " runs=" << data_.train().size()
     << " refine=" << cfg_.refine_latents << " latent_noise=" << cfg_.latent_noise;
  // Appended only when set, so checkpoints written before the option existed still resume.
  if (n.encoder_channels != EncoderImpl::kChannels)
    os << " encoder_channels=" << n.encoder_channels;
  if (n.encoder_max_length != EncoderImpl::kMaxLength)
    os << " encoder_max_length=" << n.encoder_max_length;
  if (n.encoder != "network") os << " encoder=" << n.encoder;
  if (n.decoder != DecoderFamily::mlp)
    os << " decoder=" << family_name(n.decoder) << " modes=" << n.modes[0] << "," << n.modes[1]
       << "," << n.modes[2] << " coefficients=" << n.coefficient_width << "x"
       << n.coefficient_depth;
  if (!opt_.base_model.empty()) os << " base=" << opt_.base_model;
  return os.str();
}

long Trainer::checkpoint_spacing() const {
  if (!model_.is_basis()) return 1;
  double bytes = 0;
  for (const BasisField& f : model_.basis)
    if (f.modes.defined()) bytes += double(f.modes.numel() + f.mean.numel()) * sizeof(float);
  return std::max(1L, long(bytes / (64.0 * 1024 * 1024)));
}

void Trainer::save_checkpoint() const {
  if (team_rank() != 0) return;  // every process holds the same state: process 0 writes it
  torch::serialize::OutputArchive a, m, o;
  model_.write(m);
  a.write("model", m);
  a.write("config_key", c10::IValue(config_key()));
  a.write("stage", c10::IValue(int64_t(stage_)));
  a.write("step", c10::IValue(int64_t(step_)));
  std::ostringstream rng;
  rng << rng_;
  a.write("rng", c10::IValue(rng.str()));
  if (adam_) {
    adam_->save(o);
    a.write("optimizer", o);
  }
  if (latents_.defined()) {
    a.write("latents", latents_, true);
    a.write("latent_frames", torch::tensor(latent_frame_, torch::kInt64), true);
  }
  for (int f = 0; f < kStageCount; ++f)
    if (targets_[f].defined()) a.write("basis_targets_" + std::to_string(f), targets_[f], true);
  torch::Tensor h = torch::empty({int64_t(history_.size()), 4}, torch::kFloat64);
  for (size_t i = 0; i < history_.size(); ++i) {
    const LossRow& r = history_[i];
    h[i][0] = r.stage, h[i][1] = double(r.step), h[i][2] = r.loss, h[i][3] = r.lr;
  }
  a.write("history", h, true);
  // Atomic (a kill mid-write leaves the previous checkpoint intact), with a checksum.
  writing_ = true;
  save_checked_archive(a, ckpt_, "checkpoint");
  writing_ = false;
}

void Trainer::load_checkpoint() {
  torch::serialize::InputArchive a, m;
  if (!load_checked_archive(a, ckpt_, "checkpoint"))  // nsf writes every checkpoint with one
    fail("checkpoint ", ckpt_,
         " is damaged: it has no checksum (bytes were appended or cut); start over with --fresh");
  c10::IValue v;
  a.read("config_key", v);
  if (v.toStringRef() != config_key())
    fail("checkpoint ", ckpt_, " was written for other settings:\n  checkpoint: ", v.toStringRef(),
         "\n  now:        ", config_key(), "\nrerun with the same options, or delete it");
  a.read("model", m);
  model_ = NeuralModel::read(m, ckpt_);  // CPU tensors, whatever device wrote it
  model_.to(dev_);
  a.read("stage", v);
  stage_ = static_cast<int>(v.toInt());
  a.read("step", v);
  step_ = v.toInt();
  a.read("rng", v);
  std::istringstream rng(v.toStringRef());
  rng >> rng_;
  torch::Tensor lat;
  if (a.try_read("latents", lat, true)) {
    latents_ = lat;
    torch::Tensor frames;
    if (a.try_read("latent_frames", frames, true))  // older checkpoints: one latent per frame
      latent_frame_.assign(frames.data_ptr<int64_t>(), frames.data_ptr<int64_t>() + frames.numel());
    else
      for (int64_t i = 0; i < latents_.size(0); ++i) latent_frame_.push_back(i);
  }
  for (int f = 0; f < kStageCount; ++f)
    a.try_read("basis_targets_" + std::to_string(f), targets_[f], true);
  torch::Tensor h;
  a.read("history", h, true);
  history_.clear();
  auto acc = h.accessor<double, 2>();
  for (int64_t i = 0; i < h.size(0); ++i)
    history_.push_back({int(acc[i][0]), long(acc[i][1]), acc[i][2], acc[i][3]});
  if (stage_ < kStageCount) {
    start_stage();
    torch::serialize::InputArchive o;
    if (step_ > 0 && a.try_read("optimizer", o)) {
      adam_->load(o);
      move_adam_state(*adam_, dev_);
    }
  }
}

}  // namespace train

}  // namespace nsf
