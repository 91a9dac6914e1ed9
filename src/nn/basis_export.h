#pragma once
// A basis model's decoders in their run-time form (nn/basis_decoders.h), copied out of the
// torch-level model (nn/model/neural_model.h): at load for the runtime, and during training for the
// latent refinement, which fits the current networks.
#include <cstdint>
#include <vector>

#include "nn/basis_decoders.h"
#include "nn/model_record.h"

namespace nsf {

class NeuralModel;

// Field f (0: x − X, 1: τ, 2: C) at the particles `ids` (all particles when null).
PointBasis point_basis(const NeuralModel& model, int field,
                       const std::vector<uint32_t>* ids = nullptr);
BasisDecoders basis_decoders(const NeuralModel& model);
// No bases, only which inputs the coefficients read (BasisDecoders::stress_input, affine_input).
BasisDecoders coefficient_inputs(const NeuralModel& model);

// The model's run-time record (nn/model_record.h): its bases (a basis model), the training runs'
// latents, the attachments, and e(X) at the rest state (evaluated here: the encoder is torch's).
ModelRecord model_record(const NeuralModel& model);

}  // namespace nsf
