#pragma once
// Spatial derivatives of the deformation field g, for what the ROM step derives from g instead of
// a network: the CROM baseline's F = ∂g/∂X (stress through the material), and the APIC affine
// matrices from the ROM's own velocity field (RomOptions::affine = velocity).
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

// C = ∂v/∂x of the velocity field v = (g(·, ẑ_n) − g(·, ẑ_{n−1}))/Δt, i.e. Ḟ F⁻¹ with
// Ḟ = (F_n − F_{n−1})/Δt: APIC's C is the velocity gradient at the particle.
void velocity_gradients(const torch::Tensor& F, const torch::Tensor& F_prev, double dt,
                        std::vector<Mat3>& C);

}  // namespace nsf
