#include "runtime/plugin_networks.h"

#include <memory>
#include <vector>

#include "core/error.h"
#include "nn/coordinate_networks.h"
#include "nn/latent_inversion.h"
#include "nn/model_record.h"
#include "runtime/mlp_plugin_library.h"

namespace nsf {

namespace {

// The plugin's answer: nothing, or nsf::Error with its message after `what`.
void check(int status, const nsf_mlp_error& e, const char* what) {
  if (status != 0) fail("the MLP plugin's ", what, ": ", e.message);
}

// The loaded model, shared by the networks and everything they hand out.
struct PluginModel {
  const nsf_mlp_plugin& api;
  nsf_mlp_model* model = nullptr;
  int r = 0;
  ~PluginModel() { api.close(model); }
};
using Model = std::shared_ptr<const PluginModel>;

std::vector<double> flat(const std::vector<Vec3>& v) {
  std::vector<double> out(3 * v.size());
  for (size_t p = 0; p < v.size(); ++p)
    for (int k = 0; k < 3; ++k) out[3 * p + k] = v[p][k];
  return out;
}
void unflat(const std::vector<double>& in, std::vector<Vec3>& out) {
  out.resize(in.size() / 3);
  for (size_t p = 0; p < out.size(); ++p) out[p] = Vec3(in[3 * p], in[3 * p + 1], in[3 * p + 2]);
}
void unflat(const std::vector<double>& in, std::vector<Mat3>& out) {
  out.resize(in.size() / 9);
  for (size_t p = 0; p < out.size(); ++p)
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) out[p](i, k) = in[9 * p + 3 * i + k];
}

struct PluginPoints final : CoordinateNetworks::Points {
  Model m;
  nsf_mlp_points* points = nullptr;
  size_t count = 0;
  ~PluginPoints() override { m->api.free_points(points); }
};

class PluginSamples final : public SampleDeformation {
 public:
  PluginSamples(Model m, nsf_mlp_samples* s, size_t n) : m_(std::move(m)), s_(s), n_(n) {}
  ~PluginSamples() override { m_->api.free_samples(s_); }
  size_t size() const override { return n_; }
  void evaluate(const Eigen::VectorXd& z, std::vector<Vec3>& g) override {
    check_latent(z);
    std::vector<double> out(3 * n_);
    nsf_mlp_error e{};
    check(m_->api.sample_values(s_, z.data(), out.data(), &e), e, "g at the samples");
    unflat(out, g);
  }
  void jacobian(const Eigen::VectorXd& z, Eigen::MatrixXd& J, std::vector<Vec3>& g) override {
    check_latent(z);
    J.resize(Eigen::Index(3 * n_), m_->r);  // column-major, as the table's J
    std::vector<double> out(3 * n_);
    nsf_mlp_error e{};
    check(m_->api.sample_jacobian(s_, z.data(), J.data(), out.data(), &e), e, "∂g/∂ẑ");
    unflat(out, g);
  }

 private:
  void check_latent(const Eigen::VectorXd& z) const {
    if (z.size() != m_->r) fail("latent of size ", z.size(), " for a model with r = ", m_->r);
  }
  Model m_;
  nsf_mlp_samples* s_;
  size_t n_;
};

class PluginNetworks final : public CoordinateNetworks {
 public:
  PluginNetworks(Model m, std::string encoder) : m_(std::move(m)), encoder_(std::move(encoder)) {}

  std::unique_ptr<Points> prepare(const std::vector<Vec3>& X) const override {
    auto p = std::make_unique<PluginPoints>();
    p->m = m_;
    p->count = X.size();
    const std::vector<double> in = flat(X);
    nsf_mlp_error e{};
    check(api().prepare(m_->model, in.data(), X.size(), &p->points, &e), e, "rest positions");
    return p;
  }

  std::vector<Eigen::VectorXd> encode(const std::vector<std::vector<Vec3>>& frames) const override {
    const size_t P = frames.empty() ? 0 : frames[0].size();
    std::vector<double> x;
    x.reserve(3 * P * frames.size());
    for (const auto& f : frames) {
      if (f.size() != P) fail("encode: frames of ", f.size(), " and ", P, " particles");
      const std::vector<double> v = flat(f);
      x.insert(x.end(), v.begin(), v.end());
    }
    std::vector<double> z(frames.size() * size_t(m_->r));
    nsf_mlp_error e{};
    check(api().encode(m_->model, x.data(), frames.size(), P, z.data(), &e), e, "encoder");
    std::vector<Eigen::VectorXd> out;
    for (size_t f = 0; f < frames.size(); ++f)
      out.emplace_back(Eigen::Map<const Eigen::VectorXd>(z.data() + f * size_t(m_->r), m_->r));
    return out;
  }

  void deform(const Points& X, const std::vector<uint32_t>* ids,
              const std::vector<const Eigen::VectorXd*>& zs, std::vector<Vec3>& x) const override {
    std::vector<double> z;
    for (const Eigen::VectorXd* v : zs) z.insert(z.end(), latent(*v), latent(*v) + m_->r);
    const size_t n = rows(X, ids);
    std::vector<double> out(3 * n * zs.size());
    nsf_mlp_error e{};
    check(api().deform(m_->model, points(X), ids ? ids->data() : nullptr, n, z.data(), zs.size(),
                       out.data(), &e),
          e, "g");
    unflat(out, x);
  }
  void stress(const Points& X, const std::vector<uint32_t>* ids, const Eigen::VectorXd& z,
              double mu, std::vector<Mat3>& tau) const override {
    const size_t n = rows(X, ids);
    std::vector<double> out(9 * n);
    nsf_mlp_error e{};
    check(api().stress(m_->model, points(X), ids ? ids->data() : nullptr, n, latent(z), mu,
                       out.data(), &e),
          e, "h");
    unflat(out, tau);
  }
  void affine(const Points& X, const std::vector<uint32_t>* ids, const Eigen::VectorXd& z,
              std::vector<Mat3>& C) const override {
    const size_t n = rows(X, ids);
    std::vector<double> out(9 * n);
    nsf_mlp_error e{};
    check(api().affine(m_->model, points(X), ids ? ids->data() : nullptr, n, latent(z), out.data(),
                       &e),
          e, "l");
    unflat(out, C);
  }
  std::unique_ptr<SampleDeformation> samples(const Points& X,
                                             const std::vector<uint32_t>& ids) const override {
    rows(X, &ids);
    nsf_mlp_samples* s = nullptr;
    nsf_mlp_error e{};
    check(api().samples(m_->model, points(X), ids.data(), ids.size(), &s, &e), e, "samples");
    return std::make_unique<PluginSamples>(m_, s, ids.size());
  }
  void deformation_gradients(const Points& X, const std::vector<uint32_t>& ids,
                             const Eigen::VectorXd& z, std::vector<Mat3>& F) const override {
    const size_t n = rows(X, &ids);
    std::vector<double> out(9 * n);
    nsf_mlp_error e{};
    check(
        api().deformation_gradients(m_->model, points(X), ids.data(), n, latent(z), out.data(), &e),
        e, "∂g/∂X");
    unflat(out, F);
  }
  const std::string& encoder_kind() const override { return encoder_; }

 private:
  const nsf_mlp_plugin& api() const { return m_->api; }
  const double* latent(const Eigen::VectorXd& z) const {
    if (z.size() != m_->r) fail("latent of size ", z.size(), " for a model with r = ", m_->r);
    return z.data();
  }
  static const nsf_mlp_points* points(const Points& X) {
    return static_cast<const PluginPoints&>(X).points;
  }
  // The result rows of a call at `ids` (null: every point), each id checked against the points.
  static size_t rows(const Points& X, const std::vector<uint32_t>* ids) {
    const size_t count = static_cast<const PluginPoints&>(X).count;
    if (!ids) return count;
    for (uint32_t i : *ids)
      if (i >= count) fail("point ", i, " of ", count, " prepared points");
    return ids->size();
  }

  Model m_;
  std::string encoder_;
};

}  // namespace

NeuralFields load_mlp_model(const std::string& path, int threads) {
  const nsf_mlp_plugin& api = mlp_plugin(path);
  if (threads > 0) api.set_threads(threads);
  nsf_mlp_error e{};
  nsf_mlp_model* handle = nullptr;
  if (api.open(path.c_str(), &handle, &e) != 0) fail(e.message);
  // Made in place: a copy's destructor would close the handle.
  std::shared_ptr<PluginModel> m(new PluginModel{api, handle, 0});
  size_t size = 0;
  check(api.record(handle, nullptr, 0, &size, &e), e, "record");
  std::string bytes(size, '\0');
  check(api.record(handle, reinterpret_cast<unsigned char*>(bytes.data()), bytes.size(), &size, &e),
        e, "record");
  ModelRecord record = decode_model_record(bytes, path);
  if (record.family != DecoderFamily::mlp)
    fail("model file ", path, ": the MLP plugin read it as a ", family_name(record.family),
         " model");
  m->r = record.latent_dim;
  char kind[64] = {};
  check(api.encoder_kind(handle, kind, sizeof kind, &e), e, "encoder kind");
  return NeuralFields::from_record(std::move(record),
                                   std::make_unique<PluginNetworks>(std::move(m), kind));
}

}  // namespace nsf
