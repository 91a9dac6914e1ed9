#include "nn/train/trainer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "core/memory.h"
#include "core/progress.h"
#include "core/timer.h"
#include "io/atomic_file.h"
#include "io/run_reader.h"
#include "nn/basis_decoders.h"
#include "nn/basis_export.h"
#include "nn/checked_archive.h"
#include "nn/dataset.h"
#include "nn/latent_inversion.h"
#include "nn/model.h"
#include "nn/network_samples.h"
#include "nn/rbf_map.h"
#include "nn/torch_settings.h"
#include "nn/train/basis_fit.h"
#include "nn/train/batch_budget.h"
#include "nn/train/loss_plot.h"

#include <torch/cuda.h>
#include <torch/optim/adam.h>

namespace nsf {

namespace fs = std::filesystem;

std::string checkpoint_path_for(const std::string& model_path) {
  return model_path + ".ckpt";
}

std::string loss_csv_path_for(const std::string& model_path) {
  return (fs::path(model_path).replace_extension("").string()) + ".loss.csv";
}

namespace {

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
// τ's Frobenius norm counts its off-diagonal entries twice (xx yy zz xy yz xz).
const std::vector<double> kBasisWeights[kStageCount] = {
    {1, 1, 1}, {1, 1, 1, M_SQRT2, M_SQRT2, M_SQRT2}, std::vector<double>(9, 1.0)};

// ≤ 0: half of what the machine has available now, at least 2 GiB (the former fixed default).
double memory_budget_gib(double requested) {
  if (requested > 0) return requested;
  return std::max(2.0, 0.5 * available_memory_mib() / 1024.0);
}

// The memory budget, once the batches are checked against it and the dataset: before the frames
// are read, and before a batch is allocated (nn/train/batch_budget.h).
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

class Trainer {
 public:
  Trainer(const std::string& data_dir, const std::string& out, const TrainOptions& o)
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
  model_.training_box = TrainingBox();
  for (const SimulationFile& r : data_.train()) model_.training_box.include(r.box);
  for (const SimulationFile& r : data_.train()) {
    ms[0] += r.mu, mq[0] += r.mu * r.mu;
    model_.mu_min = std::min(model_.mu_min, r.mu), model_.mu_max = std::max(model_.mu_max, r.mu);
  }
  model_.norm_mu = Normalizer::from_moments(ms, mq, double(data_.train().size()));
}

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

const std::vector<float>& Trainer::frame_field(size_t i, int f) {
  if (f == 0 || !store_.positions_only()) {
    const FrameData& d = store_.get(i);
    return f == 0 ? d.x : f == 1 ? d.tau : d.C;
  }
  field_scratch_ =
      data_.read_field(data_.train()[store_.sim_of(i)], store_.frame_of(i), f == 1 ? "tau" : "C");
  return field_scratch_;
}

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

torch::Tensor Trainer::entries(const torch::Tensor& t, const std::vector<int64_t>& rows) const {
  if (!team_) return t;  // a single process computes every entry
  return t.index_select(0, torch::tensor(rows, torch::kInt64).to(t.device()));
}

double Trainer::sum_over_team(double loss) {
  if (!team_) return loss;
  // Every parameter's gradient (zeros where this process computed no entry) and the loss, in
  // one buffer: one MPI_Allreduce per step.
  std::vector<torch::Tensor> grads;
  size_t count = 1;
  for (auto& group : adam_->param_groups())
    for (auto& p : group.params()) {
      if (!p.grad().defined()) p.mutable_grad() = torch::zeros_like(p);
      grads.push_back(p.grad());
      count += size_t(p.numel());
    }
  std::vector<float> flat(count);
  size_t at = 0;
  for (const torch::Tensor& g : grads) {
    const torch::Tensor c = g.to(torch::kCPU).contiguous();
    std::copy_n(c.data_ptr<float>(), c.numel(), flat.data() + at);
    at += size_t(c.numel());
  }
  flat[at] = float(loss);
  team_->sum(flat.data(), flat.size());
  at = 0;
  for (torch::Tensor& g : grads) {
    g.copy_(torch::from_blob(flat.data() + at, g.sizes()));
    at += size_t(g.numel());
  }
  return double(flat[at]);
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

void Trainer::write_loss_curves(TrainReport& report) const {
  report.loss_csv = loss_csv_path_for(out_);
  std::ostringstream csv;
  csv << "stage,network,step,loss,loss_smooth,lr\n";
  // A trailing mean over 50 steps: single-batch losses are too noisy to read a trend from.
  double window_sum = 0;
  std::vector<double> window;
  int last_stage = -1;
  for (const LossRow& r : history_) {
    if (r.stage != last_stage) window.clear(), window_sum = 0, last_stage = r.stage;
    window.push_back(r.loss);
    window_sum += r.loss;
    if (window.size() > 50) window_sum -= window[window.size() - 51];
    const double smooth = window_sum / double(std::min<size_t>(window.size(), 50));
    csv << r.stage + 1 << "," << kNetworkNames[r.stage] << "," << r.step << "," << r.loss << ","
        << smooth << "," << r.lr << "\n";
  }
  write_file_atomic(report.loss_csv, csv.str());
  if (history_.empty()) {  // stage 1 from a base model, maps for τ and C: nothing was stepped
    say("note: no optimiser steps in this run (coefficient maps only), so no loss curves");
    return;
  }
  const std::string png = fs::path(report.loss_csv).replace_extension(".png").string();
  const std::string no_plot =
      plot_loss_curves(report.loss_csv, png, "nsf train: " + model_.scene.scene_name);
  if (no_plot.empty())
    report.loss_png = png;
  else
    say("note: " + no_plot + ", loss curves only as CSV (" + report.loss_csv + ")");
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
    // A base model's calibrations were of other fields.
    model_.calibration = model_.tracked_calibration = RomCalibration();
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

void Trainer::share_setup() {
  if (!team_) return;
  std::string bytes;
  if (team_rank() == 0) {
    torch::serialize::OutputArchive a, m;
    model_.write(m);
    a.write("model", m);
    for (int f = 0; f < kStageCount; ++f)
      if (targets_[f].defined()) a.write("basis_targets_" + std::to_string(f), targets_[f], true);
    std::ostringstream os;
    a.save_to(os);
    bytes = os.str();
  }
  team_->broadcast(bytes);
  if (team_rank() == 0) return;
  std::istringstream is(bytes);
  torch::serialize::InputArchive a, m;
  a.load_from(is);
  a.read("model", m);
  model_ = NeuralModel::read(m, "the model of process 0");
  for (int f = 0; f < kStageCount; ++f)
    a.try_read("basis_targets_" + std::to_string(f), targets_[f], true);
}

}  // namespace

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
  Trainer t(data_dir, out_path, options);
  return t.run();
}

}  // namespace nsf
