#pragma once
// Checks a training run's batch sizes against the dataset and the memory budget before anything
// is allocated: `nsf train --frames-per-batch 1000000000` used to grow memory without bound.
#include <cstddef>

#include "nn/config.h"

namespace nsf {

// Bytes one optimiser step of stage `stage` holds, roughly (batch inputs, targets, activations and
// their gradients), for a dataset of `particles` particles.
double step_bytes(const TrainConfig& c, int stage, size_t particles);

// Throws nsf::Error naming the option when a stage's batch holds more frames than the
// `training_frames` of the dataset, or one step would need more than `budget_gib` of memory.
void check_batch_sizes(const TrainConfig& c, size_t training_frames, size_t particles,
                       double budget_gib);

}  // namespace nsf
