#include "rom/field_gradients.h"

#include <torch/torch.h>

#include <Eigen/LU>

#include "core/error.h"
#include "nn/model.h"

namespace nsf {

namespace {
using RowMat3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
}

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

void velocity_gradients(const torch::Tensor& F, const torch::Tensor& F_prev, double dt,
                        std::vector<Mat3>& C) {
  if (F.sizes() != F_prev.sizes() || F.dim() != 3 || F.size(1) != 3 || F.size(2) != 3)
    fail("velocity gradients: F and F_prev must both be m x 3 x 3");
  if (!(dt > 0)) fail("velocity gradients: the time step must be positive, got ", dt);
  const torch::Tensor a = F.to(torch::kFloat64).contiguous(),
                      b = F_prev.to(torch::kFloat64).contiguous();
  const double* f = a.data_ptr<double>();
  const double* fp = b.data_ptr<double>();
  C.resize(size_t(F.size(0)));
  for (int64_t k = 0; k < F.size(0); ++k) {
    const Mat3 Fn = Eigen::Map<const RowMat3>(f + 9 * k);
    const Mat3 Fdot = (Fn - Mat3(Eigen::Map<const RowMat3>(fp + 9 * k))) / dt;
    C[size_t(k)] = Fdot * Fn.inverse();
  }
}

}  // namespace nsf
