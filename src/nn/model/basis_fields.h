#pragma once
// One field of a basis model at the torch level, f_p = mean_p + B_p · (scale ⊙ net(input)): what
// training fits and the model file stores (nn/basis_decoders.h has the torch-free run-time form,
// nn/basis_export.h copies one into the other). The bases come from the training frames
// (nn/train/basis_fit.h); the coefficients' inputs are NeuralModel::coefficient_input
// (nn/model/basis_fields.cpp).
#include <cstdint>

#include "nn/networks.h"

namespace nsf {

struct BasisField {
  torch::Tensor mean;   // |P| × dim
  torch::Tensor modes;  // |P| × dim × K
  torch::Tensor scale;  // K: each coefficient's spread over the training frames
  FieldMlp net{nullptr};
  // The coefficient map instead of the network (τ and C of a model with maps: nn/rbf_map.h),
  // float64; undefined until its stage has run.
  torch::Tensor map_centers, map_weights, map_poly, map_shift, map_scale;
  bool has_map() const { return map_centers.defined(); }
  int64_t K() const { return scale.defined() ? scale.size(0) : 0; }
};

}  // namespace nsf
