// The encoder e of a model (NeuralModel::encode, nn/model/neural_model.h): the trained
// convolutional network, or a basis model's projection on its leading modes of x − X.
#include <ATen/Parallel.h>

#include "nn/model/neural_model.h"

namespace nsf {

torch::Tensor NeuralModel::encode(const torch::Tensor& x) {
  if (config.encoder == "modes") {
    // ẑ_i = Σ_p B_p,i · (x_p − X_p − mean_p) / spread_i for the first r modes (orthonormal over
    // the particles in the fit's norm, which for x − X is the plain one).
    const BasisField& b = basis[0];
    const int64_t r = latent_dim();
    // Summed in double, one frame at a time and in particle order, so that the latent has the
    // same bits at every thread count (a float product over 3|P| splits its sum across threads).
    const torch::Tensor u = (x - rest.unsqueeze(0) - b.mean.unsqueeze(0))
                                .reshape({x.size(0), -1})
                                .to(torch::kCPU, torch::kFloat64)
                                .contiguous();
    const torch::Tensor B =
        b.modes.narrow(2, 0, r).reshape({-1, r}).to(torch::kCPU, torch::kFloat64).contiguous();
    const int64_t frames = u.size(0), n = u.size(1);
    torch::Tensor z = torch::zeros({frames, r}, u.options());
    const double* up = u.data_ptr<double>();
    const double* Bp = B.data_ptr<double>();
    double* zp = z.data_ptr<double>();
    at::parallel_for(0, frames, 1, [&](int64_t begin, int64_t end) {
      for (int64_t f = begin; f < end; ++f)
        for (int64_t j = 0; j < n; ++j)
          for (int64_t i = 0; i < r; ++i) zp[f * r + i] += up[f * n + j] * Bp[j * r + i];
    });
    return (z.to(x.device(), x.scalar_type()) / b.scale.narrow(0, 0, r));
  }
  const torch::Tensor xn = displacement ? norm_u.apply(x - rest.unsqueeze(0)) : norm_x.apply(x);
  return encoder->forward(xn.reshape({x.size(0), -1}));
}

}  // namespace nsf
