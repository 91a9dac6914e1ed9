#include "nn/networks.h"

#include <ATen/Context.h>
#include <torch/nn/init.h>

#include <string>

#include "core/error.h"

namespace nsf {

namespace {

void xavier(torch::Tensor& weight, torch::Tensor& bias) {
  torch::NoGradGuard no_grad;
  torch::nn::init::xavier_uniform_(weight);
  torch::nn::init::zeros_(bias);
}

}  // namespace

EncoderImpl::EncoderImpl(int64_t particles, int64_t latent_dim, int64_t hidden,
                         int64_t conv_channels, int64_t max_length)
    : particles_(particles) {
  // MKL-DNN (oneDNN) sets up a primitive per call; for these thin 1-3 channel convolutions that
  // overhead made one stage-1 step's encoder backward pass ~50 ms instead of ~3 ms (4 frames of
  // 5 056 particles, 2 threads). Torch's native convolution is used instead, process-wide; the
  // decoders (Linear → BLAS) do not go through MKL-DNN in float32 either way.
  at::globalContext().setUserEnabledMkldnn(false);
  if (particles < 1 || latent_dim < 1 || hidden < 1 || conv_channels < 1)
    fail("encoder: need at least one particle and positive sizes (got ", particles,
         " particles, r = ", latent_dim, ", hidden ", hidden, ", channels ", conv_channels, ")");
  if (max_length < kKernel - 1)
    fail("encoder: the maximum length must be at least ", kKernel - 1, " (got ", max_length, ")");
  int64_t length = 3 * particles, channels = 1;
  while (length > max_length) {
    auto conv = torch::nn::Conv1d(
        torch::nn::Conv1dOptions(channels, conv_channels, kKernel).stride(kStride));
    xavier(conv->weight, conv->bias);
    convs_.push_back(register_module("conv" + std::to_string(convs_.size()), conv));
    length = (length - kKernel) / kStride + 1;
    channels = conv_channels;
  }
  flat_ = channels * length;
  fc1_ = register_module("fc1", torch::nn::Linear(flat_, hidden));
  fc2_ = register_module("fc2", torch::nn::Linear(hidden, latent_dim));
  xavier(fc1_->weight, fc1_->bias);
  xavier(fc2_->weight, fc2_->bias);
}

torch::Tensor EncoderImpl::forward(const torch::Tensor& x) {
  if (x.dim() != 2 || x.size(1) != 3 * particles_)
    fail("encoder built for ", particles_, " particles got input of shape ", x.sizes());
  torch::Tensor y = x.unsqueeze(1);  // B × 1 channel × 3|P|
  for (auto& conv : convs_) y = torch::elu(conv->forward(y));
  y = y.flatten(1);  // "reshaped to 1 channel"
  return fc2_->forward(torch::elu(fc1_->forward(y)));
}

FieldMlpImpl::FieldMlpImpl(int64_t in, int64_t out, int64_t width, int64_t depth)
    : in_(in), out_(out) {
  if (in < 1 || out < 1 || width < 1 || depth < 1)
    fail("decoder MLP needs positive sizes (in ", in, ", out ", out, ", width ", width, ", depth ",
         depth, ")");
  int64_t fan_in = in;
  for (int64_t i = 0; i <= depth; ++i) {
    const int64_t fan_out = i < depth ? width : out;
    auto layer = torch::nn::Linear(fan_in, fan_out);
    xavier(layer->weight, layer->bias);
    layers_.push_back(register_module("fc" + std::to_string(i), layer));
    fan_in = fan_out;
  }
}

torch::Tensor FieldMlpImpl::forward(torch::Tensor x) {
  const size_t last = layers_.size() - 1;
  for (size_t i = 0; i < last; ++i) x = torch::elu(layers_[i]->forward(x));
  return layers_[last]->forward(x);
}

}  // namespace nsf
