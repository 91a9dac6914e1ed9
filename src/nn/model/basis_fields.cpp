// A basis model's coefficients (nn/model/basis_fields.h): each field's network on its inputs,
// scaled back to physical units.
#include "nn/model/neural_model.h"

namespace nsf {

torch::Tensor NeuralModel::coefficient_input(int field, const torch::Tensor& z,
                                             const torch::Tensor& mu) const {
  if (field == 0) return z;  // as g sees it: the encoder's raw latent
  if (field == 1 && stress_has_mu()) return torch::cat({norm_z.apply(z), norm_mu.apply(mu)}, 1);
  return norm_z.apply(z);
}

torch::Tensor NeuralModel::coefficients(int field, const torch::Tensor& z,
                                        const torch::Tensor& mu) {
  BasisField& b = basis[field];
  return b.net->forward(coefficient_input(field, z, mu)) * b.scale;
}

}  // namespace nsf
