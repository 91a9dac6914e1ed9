#pragma once
// The encoder e(xⁿ) → ẑ and the decoder MLP used for g, h and l (App. E), as LibTorch modules.
// Only src/nn and the CLI include this header: the engine and its tests never see torch.
#include <torch/nn/module.h>
#include <torch/nn/modules/conv.h>
#include <torch/nn/modules/linear.h>
#include <torch/nn/pimpl.h>

#include <vector>

namespace nsf {

// e: the flattened positions of one frame (3|P| values, x y z per particle, one channel) →
// ẑ ∈ R^r. Conv1d(kernel 6, stride 4, 3 channels) layers until the length is ≤ 12, flatten,
// Linear → 32, Linear → r, ELU between. The layer count follows from |P|, so an encoder only
// accepts the particle count it was built for. `channels` widens the convolutions beyond App. E's
// 3, whose flattened bottleneck of at most 36 features limits scenes with rigid-like motion
// (docs/TRAINING.md); `max_length` (≥ 5, so that every convolution has a full kernel) stops them
// earlier, so that the Linear sees a longer sequence.
class EncoderImpl : public torch::nn::Module {
 public:
  EncoderImpl(int64_t particles, int64_t latent_dim, int64_t hidden = 32,
              int64_t channels = kChannels, int64_t max_length = kMaxLength);
  // x: B × 3|P| (normalised positions, particle-major) → B × r.
  torch::Tensor forward(const torch::Tensor& x);

  int64_t particles() const { return particles_; }
  int64_t conv_layers() const { return static_cast<int64_t>(convs_.size()); }
  int64_t flat_length() const { return flat_; }  // channels × final length, the Linear's input

  static constexpr int64_t kKernel = 6, kStride = 4, kChannels = 3, kMaxLength = 12;

 private:
  int64_t particles_, flat_;
  std::vector<torch::nn::Conv1d> convs_;
  torch::nn::Linear fc1_{nullptr}, fc2_{nullptr};
};
TORCH_MODULE(Encoder);

// A neural field decoder: ELU MLP with `depth` hidden layers of width `width`, Xavier-uniform
// weights and zero biases. Input (X, ẑ[, μ]) already normalised, output normalised.
class FieldMlpImpl : public torch::nn::Module {
 public:
  FieldMlpImpl(int64_t in, int64_t out, int64_t width, int64_t depth);
  torch::Tensor forward(torch::Tensor x);

  int64_t in_features() const { return in_; }
  int64_t out_features() const { return out_; }
  const std::vector<torch::nn::Linear>& layers() const { return layers_; }

 private:
  int64_t in_, out_;
  std::vector<torch::nn::Linear> layers_;  // depth hidden layers, then the output layer
};
TORCH_MODULE(FieldMlp);

}  // namespace nsf
