// The encoder and the coordinate networks of a model loaded with LibTorch
// (nn/coordinate_networks.h), NeuralFields::load, which attaches them, and the nn-internal way
// back to the torch-level model (nn/model/access.h).
#include <torch/torch.h>

#include "core/error.h"
#include "io/run_format.h"
#include "nn/basis_export.h"
#include "nn/coordinate_networks.h"
#include "nn/model/access.h"
#include "nn/model/neural_model.h"
#include "nn/network_samples.h"
#include "nn/neural_fields.h"

namespace nsf {

namespace {

// Bounds the activations of one call (points × width floats per layer) for large point sets.
constexpr int64_t kChunk = 65536;

torch::Tensor positions_tensor(const std::vector<Vec3>& v) {
  return torch::from_blob(const_cast<double*>(v.data()->data()), {int64_t(v.size()), 3},
                          torch::kFloat64)
      .to(torch::kFloat32);
}

torch::Tensor latent_row(const Eigen::VectorXd& z) {  // 1 × r, float
  return torch::from_blob(const_cast<double*>(z.data()), {1, int64_t(z.size())}, torch::kFloat64)
      .to(torch::kFloat32);
}

torch::Tensor index_tensor(const std::vector<uint32_t>& ids) {
  torch::Tensor t = torch::empty({int64_t(ids.size())}, torch::kInt64);
  int64_t* p = t.data_ptr<int64_t>();
  for (size_t k = 0; k < ids.size(); ++k) p[k] = ids[k];
  return t;
}

// Rows of an n × w tensor as run files order them (io/run_format.h): positions (w = 3), symmetric
// τ (6: xx yy zz xy yz xz) or row-major matrices (9).
template <typename T, typename Unpack>
void rows_of(const torch::Tensor& t, std::vector<T>& out, Unpack unpack) {
  const torch::Tensor d = t.to(torch::kFloat64).contiguous();
  const int64_t w = d.dim() == 2 ? d.size(1) : 0;
  const double* p = d.data_ptr<double>();
  out.resize(size_t(d.size(0)));
  for (size_t k = 0; k < out.size(); ++k) out[k] = unpack(p + int64_t(k) * w);
}
void vec3_rows(const torch::Tensor& t, std::vector<Vec3>& out) {
  rows_of(t, out, run_format::unpack_vec);
}
void symmetric_rows(const torch::Tensor& t, std::vector<Mat3>& out) {
  rows_of(t, out, run_format::unpack_sym);
}
void matrix_rows(const torch::Tensor& t, std::vector<Mat3>& out) {
  rows_of(t, out, run_format::unpack_mat);
}

struct TorchPoints final : CoordinateNetworks::Points {
  torch::Tensor Xn;  // N × 3 normalised rest positions
};

class TorchNetworks final : public CoordinateNetworks {
 public:
  explicit TorchNetworks(NeuralModel model) : model_(std::move(model)) {}

  std::unique_ptr<Points> prepare(const std::vector<Vec3>& X) const override {
    check_mlp();
    auto p = std::make_unique<TorchPoints>();
    p->Xn = X.empty() ? torch::empty({0, 3}) : model_.norm_X.apply(positions_tensor(X));
    return p;
  }

  std::vector<Eigen::VectorXd> encode(const std::vector<std::vector<Vec3>>& frames) const override {
    torch::NoGradGuard no_grad;
    const int64_t P = model_.scene.particles;
    std::vector<Eigen::VectorXd> out;
    for (const auto& x : frames) {
      const torch::Tensor z =
          m().encode(positions_tensor(x).reshape({1, P, 3})).to(torch::kFloat64).contiguous();
      out.emplace_back(Eigen::Map<const Eigen::VectorXd>(z.data_ptr<double>(), z.size(1)));
    }
    return out;
  }

  void deform(const Points& X, const std::vector<uint32_t>* ids,
              const std::vector<const Eigen::VectorXd*>& zs, std::vector<Vec3>& x) const override {
    check_mlp();
    torch::NoGradGuard no_grad;
    if (!ids) {  // every point, one latent, in chunks
      vec3_rows(
          chunked(X, *zs.at(0), [&](const auto& a, const auto& b) { return m().deform(a, b); }), x);
      return;
    }
    const torch::Tensor Xn = rows(X, *ids);
    const int64_t n = Xn.size(0);
    std::vector<torch::Tensor> Xs, z_rows;
    for (const Eigen::VectorXd* z : zs)
      Xs.push_back(Xn), z_rows.push_back(latent_row(*z).expand({n, z->size()}));
    vec3_rows(
        zs.size() == 1 ? m().deform(Xn, z_rows[0]) : m().deform(torch::cat(Xs), torch::cat(z_rows)),
        x);
  }

  void stress(const Points& X, const std::vector<uint32_t>* ids, const Eigen::VectorXd& z,
              double mu, std::vector<Mat3>& tau) const override {
    check_mlp();
    torch::NoGradGuard no_grad;
    if (!ids) {
      const torch::Tensor mus = torch::full({1, 1}, float(mu));
      symmetric_rows(chunked(X, z,
                             [&](const auto& a, const auto& b) {
                               return m().stress(a, b, mus.expand({a.size(0), 1}));
                             }),
                     tau);
      return;
    }
    const int64_t n = int64_t(ids->size());
    symmetric_rows(m().stress(rows(X, *ids), latent_row(z).expand({n, z.size()}),
                              torch::full({n, 1}, float(mu))),
                   tau);
  }

  void affine(const Points& X, const std::vector<uint32_t>* ids, const Eigen::VectorXd& z,
              std::vector<Mat3>& C) const override {
    check_mlp();
    torch::NoGradGuard no_grad;
    if (!ids) {
      matrix_rows(chunked(X, z, [&](const auto& a, const auto& b) { return m().affine(a, b); }), C);
      return;
    }
    const int64_t n = int64_t(ids->size());
    matrix_rows(m().affine(rows(X, *ids), latent_row(z).expand({n, z.size()})), C);
  }

  std::unique_ptr<SampleDeformation> samples(const Points& X,
                                             const std::vector<uint32_t>& ids) const override {
    check_mlp();
    return std::make_unique<NetworkSamples>(m(), rows(X, ids));
  }

  void deformation_gradients(const Points& X, const std::vector<uint32_t>& ids,
                             const Eigen::VectorXd& z, std::vector<Mat3>& F) const override {
    check_mlp();
    const int64_t n = int64_t(ids.size());
    const torch::Tensor G =
        nsf::deformation_gradients(m(), rows(X, ids), latent_row(z).expand({n, z.size()}));
    const double* f = G.data_ptr<double>();
    F.resize(ids.size());
    for (int64_t k = 0; k < n; ++k)
      F[size_t(k)] = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(f + 9 * k);
  }

  const std::string& encoder_kind() const override { return model_.config.encoder; }
  NeuralModel& model() { return model_; }

 private:
  // The networks' forward passes change no parameter: const at this interface.
  NeuralModel& m() const { return const_cast<NeuralModel&>(model_); }

  void check_mlp() const {
    if (model_.is_basis())
      fail(
          "rom: this source evaluates or differentiates the paper's coordinate networks, and this "
          "is a per-point basis model (nsf train --decoder basis): use the basis sources");
  }

  static const torch::Tensor& points(const Points& X) {
    return static_cast<const TorchPoints&>(X).Xn;
  }
  static torch::Tensor rows(const Points& X, const std::vector<uint32_t>& ids) {
    return points(X).index_select(0, index_tensor(ids));
  }

  // Runs f over chunks of the prepared points and returns the concatenated rows as double.
  template <typename F>
  torch::Tensor chunked(const Points& X, const Eigen::VectorXd& z, F&& f) const {
    const torch::Tensor& Xn = points(X);
    const torch::Tensor zt = latent_row(z);
    const int64_t n = Xn.size(0);
    std::vector<torch::Tensor> parts;
    for (int64_t a = 0; a < n; a += kChunk) {
      const torch::Tensor Xa = Xn.slice(0, a, std::min(n, a + kChunk));
      parts.push_back(f(Xa, zt.expand({Xa.size(0), zt.size(1)})));
    }
    if (parts.empty()) return torch::empty({0, 0}, torch::kFloat64);
    return torch::cat(parts, 0).to(torch::kFloat64).contiguous();
  }

  NeuralModel model_;
};

}  // namespace

NeuralFields NeuralFields::load(const std::string& path) {
  NeuralModel model = NeuralModel::load(path);
  NeuralFields f;
  // A basis model's fields as the torch-free runtime reads them, from the same record.
  f.record_ = model.stored_record ? *model.stored_record : model_record(model);
  // The archive's attachments: a file of format version 8 kept the ROM's calibration's table
  // there alone (its record had only the numbers).
  f.record_.attachments = model.attachments;
  model.stored_record.reset();
  f.net_ = std::make_unique<TorchNetworks>(std::move(model));
  return f;
}

void NeuralFields::store_attachment(const std::string& path, const std::string& name,
                                    const std::string& text) {
  NeuralModel model = NeuralModel::load(path);
  model.attachments[name] = text;
  model.save(path);  // atomic: tmp + rename
}

NeuralModel& torch_model(NeuralFields& fields) {
  // The only networks NeuralFields::load attaches; the const is the facade's, not the model's.
  const auto* nets = dynamic_cast<const TorchNetworks*>(fields.networks());
  if (!nets)
    fail(
        "the torch-level model needs LibTorch, and this model was loaded without it "
        "(NeuralFields::load_basis): use NeuralFields::load");
  return const_cast<TorchNetworks*>(nets)->model();
}

}  // namespace nsf
