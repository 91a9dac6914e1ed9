#include "nn/basis_export.h"

#include <torch/torch.h>

#include "core/error.h"
#include "nn/model/neural_model.h"

namespace nsf {

namespace {

Eigen::VectorXd to_vector(const torch::Tensor& t) {
  const torch::Tensor d = t.to(torch::kCPU, torch::kFloat64).contiguous().reshape({-1});
  return Eigen::Map<const Eigen::VectorXd>(d.data_ptr<double>(), d.numel());
}

Eigen::MatrixXd to_matrix(const torch::Tensor& t) {
  const torch::Tensor d = t.to(torch::kCPU, torch::kFloat64).contiguous();
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      d.data_ptr<double>(), d.size(0), d.size(1));
}

RbfMap coefficient_map(const BasisField& b) {
  RbfMap m;
  m.centers = to_matrix(b.map_centers);
  m.weights = to_matrix(b.map_weights);
  m.poly = to_matrix(b.map_poly);
  m.shift = to_vector(b.map_shift);
  m.scale = to_vector(b.map_scale);
  return m;
}

// The network's layers, and the normalisation of its input that coefficient_input applies.
CoefficientNet coefficient_net(const NeuralModel& m, int field) {
  const BasisField& b = m.basis[field];
  CoefficientNet net;
  for (const torch::nn::Linear& layer : b.net->layers()) {
    const torch::Tensor w = layer->weight.detach().to(torch::kCPU, torch::kFloat64).contiguous();
    net.W.push_back(
        Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
            w.data_ptr<double>(), w.size(0), w.size(1)));
    net.b.push_back(to_vector(layer->bias.detach()));
  }
  const int64_t r = m.latent_dim(), in = b.net->in_features();
  net.in_shift = Eigen::VectorXd::Zero(in);
  net.in_scale = Eigen::VectorXd::Ones(in);
  if (field > 0) {  // h and l's latents are normalised; g's is the encoder's own
    net.in_shift.head(r) = to_vector(m.norm_z.mean);
    net.in_scale.head(r) = to_vector(m.norm_z.std);
    if (in > r)
      net.in_shift[r] = to_vector(m.norm_mu.mean)[0], net.in_scale[r] = to_vector(m.norm_mu.std)[0];
  }
  net.out_scale = to_vector(b.scale);
  return net;
}

}  // namespace

PointBasis point_basis(const NeuralModel& m, int field, const std::vector<uint32_t>* ids) {
  if (!m.is_basis()) fail("internal error: point_basis of a model without bases");
  const BasisField& b = m.basis[field];
  PointBasis out;
  out.dim = int(b.mean.size(1));
  out.K = int(b.K());
  torch::Tensor mean = b.mean, modes = b.modes;
  if (ids) {
    torch::Tensor index = torch::empty({int64_t(ids->size())}, torch::kInt64);
    for (size_t k = 0; k < ids->size(); ++k) index[int64_t(k)] = int64_t((*ids)[k]);
    mean = mean.index_select(0, index), modes = modes.index_select(0, index);
  }
  mean = mean.to(torch::kCPU, torch::kFloat32).contiguous();
  modes = modes.to(torch::kCPU, torch::kFloat32).contiguous();
  out.points = size_t(mean.size(0));
  out.mean.assign(mean.data_ptr<float>(), mean.data_ptr<float>() + mean.numel());
  out.modes.assign(modes.data_ptr<float>(), modes.data_ptr<float>() + modes.numel());
  out.net = coefficient_net(m, field);
  if (m.config.uses_map(field)) {
    if (!b.has_map())
      fail("the model has no coefficient map for ", field == 1 ? "tau" : "C",
           " (the checkpoint of a training that has not reached its stage?)");
    out.map = coefficient_map(b);
  }
  return out;
}

BasisDecoders coefficient_inputs(const NeuralModel& m) {
  BasisDecoders d;
  d.stress_uses_mu = m.stress_has_mu();
  d.affine_uses_velocity = m.config.affine_reads_velocity();
  d.stress_uses_velocity = m.config.stress_reads_velocity();
  return d;
}

BasisDecoders basis_decoders(const NeuralModel& m) {
  BasisDecoders d = coefficient_inputs(m);
  d.u = point_basis(m, 0), d.tau = point_basis(m, 1), d.C = point_basis(m, 2);
  const torch::Tensor rest = m.rest.to(torch::kFloat64).contiguous();
  const double* x = rest.data_ptr<double>();
  d.rest.resize(size_t(rest.size(0)));
  for (size_t p = 0; p < d.rest.size(); ++p) d.rest[p] = Vec3(x[3 * p], x[3 * p + 1], x[3 * p + 2]);
  return d;
}

ModelRecord model_record(const NeuralModel& m) {
  ModelRecord r;
  r.scene = m.scene;
  r.family = m.config.decoder;
  r.latent_dim = int(m.latent_dim());
  r.stress_uses_mu = m.stress_has_mu();
  r.mu_min = m.mu_min, r.mu_max = m.mu_max;
  r.training_box = m.training_box;
  r.train_seconds = m.train_seconds;
  r.attachments = m.attachments;
  r.latent_spread = to_vector(m.norm_z.std);
  if (m.trajectory_latents.defined()) {
    const torch::Tensor t = m.trajectory_latents.to(torch::kCPU, torch::kFloat64).contiguous();
    const int64_t runs = t.size(0), frames = t.size(1), dim = t.size(2);
    const double* z = t.data_ptr<double>();
    for (int64_t i = 0; i < runs; ++i) {
      r.trajectory_latents.emplace_back();
      for (int64_t k = 0; k < frames; ++k)
        r.trajectory_latents.back().push_back(
            Eigen::Map<const Eigen::VectorXd>(z + (i * frames + k) * dim, dim));
    }
    const Eigen::VectorXd mu = to_vector(m.trajectory_mu);
    r.trajectory_mu.assign(mu.data(), mu.data() + mu.size());
  }
  if (m.is_basis()) {
    r.bases = std::make_shared<BasisDecoders>(basis_decoders(m));
    // e(X) as NeuralFields::encode evaluates it for the scene's rest positions (float X). The
    // forward pass changes no parameter.
    torch::NoGradGuard no_grad;
    const torch::Tensor X = m.rest.to(torch::kCPU, torch::kFloat32).reshape({1, -1, 3});
    r.rest_latent = to_vector(const_cast<NeuralModel&>(m).encode(X));
  }
  return r;
}

}  // namespace nsf
