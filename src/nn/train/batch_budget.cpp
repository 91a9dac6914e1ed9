#include "nn/train/batch_budget.h"

#include <algorithm>

#include "core/error.h"

namespace nsf {

namespace {

constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
constexpr int kTargetDim[kStageCount] = {3, 6, 9};
// Copies of a stage-1 frame a step holds, generously: the batch, its normalised displacements, the
// encoder's activations and their gradients.
constexpr double kFrameCopies = 8;
// A basis model's stages 2 and 3 take this many latent rows per step (nn/train/trainer.cpp).
constexpr double kBasisRows = 256;

}  // namespace

double step_bytes(const TrainConfig& c, int stage, size_t particles) {
  const double P = double(particles), B = double(c.frames_per_batch[stage]);
  const NetConfig& n = c.net;
  if (n.decoder == DecoderFamily::basis) {
    const double K = n.modes[stage];
    if (stage == 0) return 4.0 * B * (kFrameCopies * 3 * P + 4 * n.coefficient_width);
    return 4.0 * kBasisRows * (K + 4.0 * n.coefficient_width * n.coefficient_depth);
  }
  const double points = B * std::min(P, double(c.particles_per_frame[stage]));
  const int widths[kStageCount] = {n.width_g, n.width_h, n.width_l};
  // Per point: inputs and targets, then each hidden layer's output, pre-activation and gradients.
  const double per_point = 4.0 + n.latent_dim + kTargetDim[stage] + 4.0 * n.depth * widths[stage];
  const double frames = stage == 0 ? B * kFrameCopies * 3 * P : 0;
  return 4.0 * (points * per_point + frames + 3 * points);  // + the particle and frame indices
}

void check_batch_sizes(const TrainConfig& c, size_t training_frames, size_t particles,
                       double budget_gib) {
  const bool basis = c.net.decoder == DecoderFamily::basis;
  for (int s = 0; s < kStageCount; ++s) {
    const int B = c.frames_per_batch[s];
    if (B < 1) fail("--frames-per-batch must be at least 1, got ", B, " (stage ", s + 1, ")");
    if (c.particles_per_frame[s] < 1)
      fail("--particles-per-frame must be at least 1, got ", c.particles_per_frame[s], " (stage ",
           s + 1, ")");
    const bool batch_used = !basis || s == 0;  // a basis model's stages 2, 3 take 256 rows
    if (batch_used && size_t(B) > training_frames)
      fail("--frames-per-batch ", B, " (stage ", s + 1, ", ", kStageNames[s],
           ") is more than the dataset's ", training_frames,
           " training frames; give at most that many");
    const double bytes = step_bytes(c, s, particles);
    if (bytes > budget_gib * kGiB)
      fail("--frames-per-batch ", B, " with --particles-per-frame ", c.particles_per_frame[s],
           " (stage ", s + 1, ", ", kStageNames[s], "): one optimiser step would hold about ",
           bytes / kGiB, " GiB, more than the memory budget of ", budget_gib,
           " GiB (--memory-budget); give smaller batches");
  }
}

}  // namespace nsf
