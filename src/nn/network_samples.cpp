#include "nn/network_samples.h"

#include <torch/torch.h>

#include <algorithm>
#include <exception>

#include "core/blas_threads.h"
#include "core/error.h"
#include "nn/basis_export.h"
#include "nn/model/access.h"
#include "nn/model/neural_model.h"

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

void deformation_jacobian(NeuralModel& model, const torch::Tensor& Xn, const Eigen::VectorXd& z,
                          Eigen::MatrixXd& J, std::vector<Vec3>& g) {
  const int64_t n = Xn.size(0), r = z.size();
  const torch::Tensor zt =
      torch::from_blob(const_cast<double*>(z.data()), {1, r}, torch::kFloat64).to(torch::kFloat32);
  // One copy of ẑ per point, so the gradient of Σ_p g_c(X_p, ẑ_p) with respect to the copies
  // holds every point's own row ∂g_c(X_p)/∂ẑ.
  torch::Tensor zrep = zt.expand({n, r}).clone().set_requires_grad(true);
  const torch::Tensor out = model.deform(Xn, zrep);  // n × 3
  J.resize(3 * n, r);
  for (int c = 0; c < 3; ++c) {
    const auto grads = torch::autograd::grad({out.select(1, c).sum()}, {zrep}, {},
                                             /*retain_graph=*/c < 2);
    const torch::Tensor G = grads[0].to(torch::kFloat64).contiguous();
    const double* Gp = G.data_ptr<double>();
    for (int64_t p = 0; p < n; ++p)
      for (int64_t k = 0; k < r; ++k) J(3 * p + c, k) = Gp[p * r + k];
  }
  const torch::Tensor o = out.detach().to(torch::kFloat64).contiguous();
  g.resize(n);
  const double* op = o.data_ptr<double>();
  for (int64_t p = 0; p < n; ++p) g[p] = Vec3(op[3 * p], op[3 * p + 1], op[3 * p + 2]);
}

NetworkSamples::NetworkSamples(NeuralModel& model, torch::Tensor Xn)
    : model_(model), Xn_(std::move(Xn)) {}

size_t NetworkSamples::size() const {
  return size_t(Xn_.size(0));
}

void NetworkSamples::evaluate(const Eigen::VectorXd& z, std::vector<Vec3>& g) {
  torch::NoGradGuard no_grad;
  const int64_t n = Xn_.size(0), r = z.size();
  const torch::Tensor zt =
      torch::from_blob(const_cast<double*>(z.data()), {1, r}, torch::kFloat64).to(torch::kFloat32);
  const torch::Tensor o = model_.deform(Xn_, zt.expand({n, r})).to(torch::kFloat64).contiguous();
  const double* op = o.data_ptr<double>();
  g.resize(n);
  for (int64_t p = 0; p < n; ++p) g[p] = Vec3(op[3 * p], op[3 * p + 1], op[3 * p + 2]);
}

void NetworkSamples::jacobian(const Eigen::VectorXd& z, Eigen::MatrixXd& J, std::vector<Vec3>& g) {
  deformation_jacobian(model_, Xn_, z, J, g);
}

std::unique_ptr<SampleDeformation> sample_deformation(NeuralModel& model,
                                                      const std::vector<Vec3>& rest,
                                                      const std::vector<uint32_t>& ids) {
  std::vector<Vec3> X(ids.size());
  for (size_t k = 0; k < ids.size(); ++k) X[k] = rest[ids[k]];
  if (model.is_basis()) return std::make_unique<BasisSamples>(point_basis(model, 0, &ids), X);
  const torch::Tensor Xn =
      model.norm_X.apply(torch::from_blob(X.data()->data(), {int64_t(X.size()), 3}, torch::kFloat64)
                             .to(torch::kFloat32));
  return std::make_unique<NetworkSamples>(model, Xn);
}

InversionResult invert_deformation(NeuralModel& model, const torch::Tensor& Xn,
                                   const std::vector<Vec3>& target, const Eigen::VectorXd& z0,
                                   const GaussNewtonOptions& options) {
  NetworkSamples samples(model, Xn);
  return invert_deformation(samples, target, z0, options);
}

FrameLatentRefiner::FrameLatentRefiner(NeuralModel& model, const std::vector<Vec3>& rest,
                                       int iterations) {
  const size_t P = rest.size(), m = std::min(kMaxParticles, P);
  std::vector<uint32_t> ids;
  for (size_t i = 0; i < m; ++i) ids_.push_back(i * P / m), ids.push_back(uint32_t(ids_.back()));
  g_ = sample_deformation(model, rest, ids);
  options_.max_iterations = iterations;
  options_.tolerance = 1e-7;
}

FrameLatentRefiner::FrameLatentRefiner(NeuralFields& fields, const std::vector<Vec3>& rest,
                                       int iterations)
    : FrameLatentRefiner(torch_model(fields), rest, iterations) {}

Eigen::VectorXd FrameLatentRefiner::refine(const float* x, const Eigen::VectorXd& start) const {
  std::vector<Vec3> target;
  target.reserve(ids_.size());
  for (size_t p : ids_) target.emplace_back(x[3 * p], x[3 * p + 1], x[3 * p + 2]);
  return invert_deformation(*g_, target, start, options_).z;
}

void FrameLatentRefiner::refine_many(const std::vector<const float*>& x,
                                     std::vector<Eigen::VectorXd>& z) const {
  if (x.size() != z.size()) fail("refine_many: ", x.size(), " frames but ", z.size(), " starts");
  // As many frames at a time as the GEMMs had threads; each of those threads gets one frame.
  const int threads = int(
      std::min<size_t>(std::max<size_t>(1, x.size()), size_t(std::max(1, blas_thread_count()))));
  const ScopedBlasThreads one_blas_thread(1);
  std::vector<std::exception_ptr> errors(x.size());
  // Inside an OpenMP region torch and Eigen run each frame's operations serially.
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
  for (size_t k = 0; k < x.size(); ++k) {
    try {
      z[k] = refine(x[k], z[k]);
    } catch (...) {
      errors[k] = std::current_exception();
    }
  }
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace nsf
