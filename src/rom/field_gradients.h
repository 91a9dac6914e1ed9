#pragma once
// Spatial derivatives of the deformation field g, for what the ROM step derives from g instead of
// a network: the CROM baseline's F = ∂g/∂X (stress through the material).
// Torch level: used by the stepper and its tests, not part of the public runtime header.
#include <torch/types.h>

#include <vector>

#include "core/types.h"

namespace nsf {

class NeuralModel;

// F = ∂g/∂X (physical rest coordinates) at the normalised rest positions Xn (m × 3, float) and
// per-particle latents zN (m × r, float), by reverse-mode autodiff: m × 3 × 3, row-major, double.
torch::Tensor deformation_gradients(NeuralModel& model, const torch::Tensor& Xn,
                                    const torch::Tensor& zN);

}  // namespace nsf
