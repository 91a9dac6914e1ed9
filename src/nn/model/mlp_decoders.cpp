// An MLP model's decoders g, h and l (the paper's coordinate networks, NeuralModel in
// nn/model/neural_model.h): their normalised inputs, which training shares, and their outputs
// in physical units.
#include "core/error.h"
#include "nn/model/neural_model.h"

namespace nsf {

torch::Tensor NeuralModel::g_input(const torch::Tensor& Xn, const torch::Tensor& z) const {
  return torch::cat({Xn, z}, 1);
}

torch::Tensor NeuralModel::h_input(const torch::Tensor& Xn, const torch::Tensor& z,
                                   const torch::Tensor& mu) const {
  if (stress_has_mu()) return torch::cat({Xn, norm_z.apply(z), norm_mu.apply(mu)}, 1);
  return torch::cat({Xn, norm_z.apply(z)}, 1);
}

torch::Tensor NeuralModel::l_input(const torch::Tensor& Xn, const torch::Tensor& z) const {
  return torch::cat({Xn, norm_z.apply(z)}, 1);
}

namespace {
void require_mlp(const NeuralModel& m, const char* what) {
  if (m.is_basis())
    fail("internal error: ", what,
         "(X, z) asked of a per-point basis model, which has no "
         "coordinate network; evaluate it through its points (nn/neural_fields.h)");
}
}  // namespace

torch::Tensor NeuralModel::deform(const torch::Tensor& Xn, const torch::Tensor& z) {
  require_mlp(*this, "g");
  if (displacement) return norm_X.invert(Xn) + norm_u.invert(g->forward(g_input(Xn, z)));
  return norm_x.invert(g->forward(g_input(Xn, z)));
}

torch::Tensor NeuralModel::stress(const torch::Tensor& Xn, const torch::Tensor& z,
                                  const torch::Tensor& mu) {
  require_mlp(*this, "h");
  return norm_tau.invert(h->forward(h_input(Xn, z, mu)));
}

torch::Tensor NeuralModel::affine(const torch::Tensor& Xn, const torch::Tensor& z) {
  require_mlp(*this, "l");
  return norm_C.invert(l->forward(l_input(Xn, z)));
}

}  // namespace nsf
