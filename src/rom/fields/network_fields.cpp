#include "rom/fields/network_fields.h"
#include "rom/fields/sources.h"

#include <torch/torch.h>

#include "core/error.h"
#include "nn/latent_inversion.h"
#include "nn/model.h"

namespace nsf {

torch::Tensor normalised_points(const NeuralModel& model, const PointTable& points) {
  if (model.is_basis())
    fail(
        "rom: this source evaluates or differentiates the paper's coordinate networks, and this "
        "is a per-point basis model (nsf train --decoder basis): use the basis sources");
  return model.norm_X.apply(torch::from_blob(const_cast<double*>(points.X.data()->data()),
                                             {int64_t(points.X.size()), 3}, torch::kFloat64)
                                .to(torch::kFloat32));
}

torch::Tensor index_tensor(const std::vector<uint32_t>& ids) {
  torch::Tensor t = torch::empty({int64_t(ids.size())}, torch::kInt64);
  int64_t* p = t.data_ptr<int64_t>();
  for (size_t k = 0; k < ids.size(); ++k) p[k] = ids[k];
  return t;
}

torch::Tensor latent_row(const Latent& z) {
  return torch::from_blob(const_cast<double*>(z.data()), {1, int64_t(z.size())}, torch::kFloat64)
      .to(torch::kFloat32);
}

void to_vec3(const torch::Tensor& t, std::vector<Vec3>& out) {
  const torch::Tensor d = t.to(torch::kFloat64).contiguous();
  const double* p = d.data_ptr<double>();
  out.resize(d.size(0));
  for (size_t k = 0; k < out.size(); ++k) out[k] = Vec3(p[3 * k], p[3 * k + 1], p[3 * k + 2]);
}

void symmetric_rows(const torch::Tensor& t, std::vector<Mat3>& out) {
  const torch::Tensor d = t.to(torch::kFloat64).contiguous();
  const double* s = d.data_ptr<double>();
  out.resize(d.size(0));
  for (size_t k = 0; k < out.size(); ++k, s += 6)
    out[k] << s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2];
}

void matrix_rows(const torch::Tensor& t, std::vector<Mat3>& out) {
  const torch::Tensor d = t.to(torch::kFloat64).contiguous();
  const double* c = d.data_ptr<double>();
  out.resize(d.size(0));
  for (size_t k = 0; k < out.size(); ++k, c += 9)
    out[k] = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(c);
}

namespace {

// What the three network sources share: the model and the table's normalised rest positions.
class NetworkPoints {
 public:
  explicit NetworkPoints(const FieldContext& c) : model_(c.fields.model()), points_(c.points) {
    set_points();
  }
  void set_points() { Xn_ = normalised_points(model_, points_); }
  torch::Tensor rows(const std::vector<uint32_t>& ids) const {
    return Xn_.index_select(0, index_tensor(ids));
  }
  NeuralModel& model() const { return model_; }

 private:
  NeuralModel& model_;
  const PointTable& points_;
  torch::Tensor Xn_;
};

class NetworkDeformation final : public DeformationSource {
 public:
  explicit NetworkDeformation(const FieldContext& c) : net_(c) {}
  std::string describe() const override { return "x from g"; }
  void set_points() override { net_.set_points(); }

  void positions(const std::vector<uint32_t>& ids, const Latent& z, const Latent&,
                 std::vector<Vec3>& x) override {
    torch::NoGradGuard no_grad;
    const int64_t m = int64_t(ids.size());
    to_vec3(net_.model().deform(net_.rows(ids), latent_row(z).expand({m, z.size()})), x);
  }

  // Both latents in one batched call.
  void positions_pair(const std::vector<uint32_t>& ids, const LatentPair& s, std::vector<Vec3>& x,
                      std::vector<Vec3>& x_prev) override {
    torch::NoGradGuard no_grad;
    const int64_t m = int64_t(ids.size()), r = s.z.size();
    const torch::Tensor Xn = net_.rows(ids);
    const torch::Tensor zz =
        torch::cat({latent_row(s.z).expand({m, r}), latent_row(s.z_prev).expand({m, r})});
    const torch::Tensor out = net_.model().deform(torch::cat({Xn, Xn}), zz);
    to_vec3(out.slice(0, 0, m), x);
    to_vec3(out.slice(0, m, 2 * m), x_prev);
  }

  std::unique_ptr<SampleDeformation> samples(const std::vector<uint32_t>& S) override {
    return std::make_unique<NetworkSamples>(net_.model(), net_.rows(S));
  }

 private:
  NetworkPoints net_;
};

class NetworkStress final : public PointFieldSource {
 public:
  explicit NetworkStress(const FieldContext& c) : net_(c), mu_(c.mu) {}
  std::string describe() const override { return "tau from h"; }
  void set_points() override { net_.set_points(); }
  void evaluate(const std::vector<uint32_t>& ids, const LatentPair& s, bool,
                std::vector<Mat3>& tau) override {
    torch::NoGradGuard no_grad;
    const int64_t m = int64_t(ids.size());
    const torch::Tensor mus = torch::full({m, 1}, float(mu_));
    symmetric_rows(
        net_.model().stress(net_.rows(ids), latent_row(s.z).expand({m, s.z.size()}), mus), tau);
  }

 private:
  NetworkPoints net_;
  double mu_;
};

class NetworkAffine final : public PointFieldSource {
 public:
  explicit NetworkAffine(const FieldContext& c) : net_(c) {}
  std::string describe() const override { return "C from l"; }
  void set_points() override { net_.set_points(); }
  void evaluate(const std::vector<uint32_t>& ids, const LatentPair& s, bool,
                std::vector<Mat3>& C) override {
    torch::NoGradGuard no_grad;
    const int64_t m = int64_t(ids.size());
    matrix_rows(net_.model().affine(net_.rows(ids), latent_row(s.z).expand({m, s.z.size()})), C);
  }

 private:
  NetworkPoints net_;
};

}  // namespace

std::unique_ptr<DeformationSource> make_network_deformation(const FieldContext& c) {
  return std::make_unique<NetworkDeformation>(c);
}
std::unique_ptr<PointFieldSource> make_network_stress(const FieldContext& c) {
  return std::make_unique<NetworkStress>(c);
}
std::unique_ptr<PointFieldSource> make_network_affine(const FieldContext& c) {
  return std::make_unique<NetworkAffine>(c);
}

}  // namespace nsf
