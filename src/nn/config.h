#pragma once
// Network sizes (App. E, Table 1) and training schedule (App. D), without torch so that the CLI,
// docs and a future runtime can talk about a model's shape without pulling in LibTorch.
#include <array>
#include <string>

namespace nsf {

// The decoder families (docs/TRAINING.md, "Decoder families"), named "basis" and "mlp" in scenes,
// options and model files.
enum class DecoderFamily { basis, mlp };
const char* family_name(DecoderFamily family);
// The family named `name`; throws nsf::Error naming `what` (an option, a key) and the families.
DecoderFamily parse_family(const std::string& name, const std::string& what);

// Shape of the three decoders and the encoder. Each decoder is an ELU MLP with `depth` hidden
// layers of width β·d (d = 3 for g, 6 for h, 9 for l), input (X, ẑ[, μ]).
struct NetConfig {
  int latent_dim = 6;  // r
  int depth = 5;       // hidden layers per decoder
  int width_g = 48 * 3;
  int width_h = 64 * 6;
  int width_l = 64 * 9;
  int encoder_hidden = 32;      // the encoder's Linear → 32 before the last Linear → r
  int encoder_channels = 3;     // output channels of each encoder convolution (App. E: 3)
  int encoder_max_length = 12;  // convolutions continue while the length exceeds this (App. E: 12)
  bool stress_uses_mu = true;   // h(X, ẑ, μ) when the dataset has a parameter μ
  // The decoder family: basis, per-point bases of the training frames times coefficients from
  // small networks of the latent (nn/basis_decoders.h), the default: more accurate and cheaper
  // per point than mlp, the paper's coordinate networks f(X, ẑ), on every scene measured.
  DecoderFamily decoder = DecoderFamily::basis;
  // The encoder of a basis model: "network", App. E's convolutions trained with c_u in stage 1,
  // or "modes", no training: ẑ_i is the training frames' i-th coefficient of x − X (its
  // projection on the i-th mode of B_u, over that coefficient's spread), so the latent is the
  // frames' r leading principal components and c_u only adds what they imply of the other modes
  // (docs/TRAINING.md, "Encoders").
  std::string encoder = "network";
  std::array<int, 3> modes = {32, 64, 64};             // K of x − X, τ and C (basis)
  int coefficient_width = 128, coefficient_depth = 3;  // the coefficient networks (basis)
  // How a basis model's stages 2 and 3 give τ's and C's coefficients: "network", small ELU
  // networks trained by Adam, or "map", thin-plate-spline maps through the training latents
  // (nn/rbf_map.h), fitted in seconds. Stage 1's c_u is always a network (the encoder learns
  // with it). The defaults are what measured best (docs/TRAINING.md, "Coefficient maps").
  std::array<std::string, 2> coefficients = {"network", "map"};  // τ, C
  bool affine_uses_velocity = true;                              // C's map reads (ẑ, μ, ż)
  // τ's map reads (ẑ[, μ], ż) too: where r leaves the phase of a vibration out of ẑ (the jelly),
  // ż carries it (docs/TRAINING.md, "Coefficient maps").
  bool stress_uses_velocity = false;
  bool uses_map(int field) const {
    return decoder == DecoderFamily::basis && field > 0 && coefficients[size_t(field - 1)] == "map";
  }
  bool uses_maps() const { return uses_map(1) || uses_map(2); }
  bool affine_reads_velocity() const { return uses_map(2) && affine_uses_velocity; }
  bool stress_reads_velocity() const { return uses_map(1) && stress_uses_velocity; }
};

// Table 1, keyed by the scene name stored in the run files; unknown scenes get the bread row.
// Returns the row's scene name ("default" for the fallback) through `matched` when given.
NetConfig default_net_config(const std::string& scene_name, std::string* matched = nullptr);

// One stage per network: 0 = encoder + g, 1 = h, 2 = l.
constexpr int kStageCount = 3;
extern const char* const kStageNames[kStageCount];  // "deformation", "stress", "affine"

// App. D's learning-rate steps, spread evenly over each stage's optimiser steps.
constexpr std::array<double, 5> kLearningRates = {1e-3, 5e-4, 2e-4, 1e-4, 5e-5};
double learning_rate(long step, long total_steps);

// What a basis model's stages 2 and 3 default to (nsf train --decoder basis): their coefficient
// networks are small, so many more steps cost seconds, and noise on their latents, which keeps
// the MLP fields tame, costs the bases accuracy at held-out μ (docs/TRAINING.md, "Decoder
// families").
constexpr long kBasisCoefficientSteps = 20000;
constexpr double kBasisLatentNoise = 0.0;

struct TrainConfig;
// `c` with its decoder family's own defaults where the command line left them open: for
// "basis", kBasisCoefficientSteps in stages 2 and 3 (unless `steps_given`) and kBasisLatentNoise
// (unless `noise_given`); nothing for "mlp".
void apply_family_defaults(TrainConfig& c, bool steps_given, bool noise_given);

struct TrainConfig {
  NetConfig net;
  // Optimiser steps per stage. Defaults are sized for a 2-core CPU (docs/TRAINING.md); the paper's
  // 300/600 epochs over all particles are out of reach there.
  std::array<long, kStageCount> steps = {6000, 1500, 1500};
  // A batch is `frames_per_batch` frames, then `particles_per_frame` particles in each, so memory
  // per step is bounded whatever the dataset size. Stage 1 also encodes each batch frame in full.
  std::array<int, kStageCount> frames_per_batch = {4, 4, 4};
  std::array<int, kStageCount> particles_per_frame = {512, 512, 512};
  // Stages 2 and 3 train h and l on the latents the reduced-order model will feed them: each
  // frame's encoder latent refined by this many Gauss–Newton iterations on positions, as the
  // ROM's inversion does (0 = the encoder's latents, as in the paper). docs/TRAINING.md.
  int refine_latents = 10;
  // Gaussian noise of this standard deviation (in units of each latent component's spread) on
  // the latents of stages 2 and 3, so h and l stay tame near the training latents.
  double latent_noise = 0.1;
  unsigned long long seed = 1;
  int threads = 0;              // 0 = all cores
  long checkpoint_every = 250;  // steps; also written at the end of every stage
  // Training frames are cached in RAM up to this many GiB, else read from disk per batch (several
  // times slower for paper-size scenes). ≤ 0: half the memory available at the start, ≥ 2 GiB.
  double memory_budget_gib = 0;
  bool quiet = false;
};

}  // namespace nsf
