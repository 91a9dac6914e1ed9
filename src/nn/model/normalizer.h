#pragma once
// Per-component affine normalisation to zero mean and unit variance: the statistics a model
// (nn/model/neural_model.h) keeps of each of its networks' inputs and outputs.
#include <torch/types.h>

#include <cstdint>
#include <vector>

namespace nsf {

struct Normalizer {
  torch::Tensor mean, std;  // float32, one entry per component

  static Normalizer identity(int64_t dim);
  // From per-component sums Σv and Σv² over `count` samples. A component that never varies
  // (τ of an unloaded direction, say) gets unit scale instead of a division by ~0.
  static Normalizer from_moments(const std::vector<double>& sum, const std::vector<double>& sum_sq,
                                 double count);
  torch::Tensor apply(const torch::Tensor& v) const { return (v - mean) / std; }
  torch::Tensor invert(const torch::Tensor& v) const { return v * std + mean; }
};

}  // namespace nsf
