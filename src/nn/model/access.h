#pragma once
// The torch-level model behind a NeuralFields loaded with LibTorch, for src/nn and the tests of
// nn alone: the facade (nn/neural_fields.h) hands out no torch type, so the ROM and the CLI reach
// the networks only through what nn offers them (nn/network_samples.h's FrameLatentRefiner, say).
namespace nsf {

class NeuralFields;
class NeuralModel;

// Throws nsf::Error when `fields` was loaded without torch (NeuralFields::load_basis).
NeuralModel& torch_model(NeuralFields& fields);

}  // namespace nsf
