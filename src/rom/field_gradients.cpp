#include "rom/field_gradients.h"

#include <torch/torch.h>

#include "nn/model.h"

namespace nsf {

torch::Tensor deformation_gradients(NeuralModel& model, const torch::Tensor& Xn,
                                    const torch::Tensor& zN) {
  torch::Tensor Xg = Xn.clone().set_requires_grad(true);
  const torch::Tensor out = model.deform(Xg, zN);
  std::vector<torch::Tensor> rows;
  for (int c = 0; c < 3; ++c)
    rows.push_back(torch::autograd::grad({out.select(1, c).sum()}, {Xg}, {}, c < 2)[0]);
  // ∂x/∂X = ∂x/∂Xn · diag(1/σ_X): the rest positions were normalised per component.
  return (torch::stack(rows, 1) / model.norm_X.std.reshape({1, 1, 3}))
      .to(torch::kFloat64)
      .contiguous();
}

}  // namespace nsf
