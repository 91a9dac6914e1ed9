// libnsf_mlp.so: the MLP plugin of the torch-free runtime. It loads an MLP model with LibTorch
// (NeuralFields::load, as the nsf tool does) and serves its networks (nn/coordinate_networks.h)
// through the C table of nn/mlp_plugin_abi.h. Every Eigen and standard object it makes stays on
// this side: results are copied into the caller's raw buffers, and errors into its message.
#include <algorithm>
#include <cstring>
#include <exception>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include "core/error.h"
#include "nn/coordinate_networks.h"
#include "nn/latent_inversion.h"
#include "nn/mlp_plugin_abi.h"
#include "nn/model_record.h"
#include "nn/neural_fields.h"
#include "nn/torch_settings.h"

struct nsf_mlp_model {
  nsf::NeuralFields fields;
  const nsf::CoordinateNetworks& net() const { return *fields.networks(); }
  int r() const { return fields.latent_dim(); }
};
struct nsf_mlp_points {
  std::unique_ptr<nsf::CoordinateNetworks::Points> points;
};
struct nsf_mlp_samples {
  std::unique_ptr<nsf::SampleDeformation> g;
  int r = 0;
  size_t n = 0;
};

namespace {

using nsf::Mat3;
using nsf::Vec3;

void set_message(nsf_mlp_error* error, const char* text) noexcept {
  if (!error) return;
  const size_t n = std::min(std::strlen(text), sizeof error->message - 1);
  std::memcpy(error->message, text, n);
  error->message[n] = '\0';
}

// Runs `body`; an exception becomes status 1 and its message.
template <typename F>
int guarded(nsf_mlp_error* error, F&& body) noexcept {
  try {
    body();
    return 0;
  } catch (const std::bad_alloc&) {
    set_message(error, "out of memory");
  } catch (const std::exception& e) {
    set_message(error, e.what());
  } catch (...) {
    set_message(error, "an unknown exception");
  }
  return 1;
}

Eigen::VectorXd latent(const nsf_mlp_model* m, const double* z) {
  return Eigen::Map<const Eigen::VectorXd>(z, m->r());
}

std::vector<uint32_t> id_list(const uint32_t* ids, size_t n) {
  return std::vector<uint32_t>(ids, ids + n);
}

// Copies v into out, which holds `rows` of them: the caller's buffer is sized for those.
void put(const std::vector<Vec3>& v, size_t rows, double* out) {
  if (v.size() != rows)
    nsf::fail("the networks gave ", v.size(), " rows, ", rows, " were asked for");
  for (size_t p = 0; p < v.size(); ++p)
    for (int k = 0; k < 3; ++k) out[3 * p + k] = v[p][k];
}
void put(const std::vector<Mat3>& m, size_t rows, double* out) {
  if (m.size() != rows)
    nsf::fail("the networks gave ", m.size(), " rows, ", rows, " were asked for");
  for (size_t p = 0; p < m.size(); ++p)
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) out[9 * p + 3 * i + k] = m[p](i, k);
}

int open_model(const char* path, nsf_mlp_model** model, nsf_mlp_error* error) {
  return guarded(error, [&] {
    auto m = std::make_unique<nsf_mlp_model>(nsf_mlp_model{nsf::NeuralFields::load(path)});
    if (m->fields.family() != nsf::DecoderFamily::mlp)
      nsf::fail("model file ", path,
                " is a basis model without a run-time record, which the runtime reads without "
                "this plugin: rewrite it with `nsf upgrade ",
                path, "`");
    *model = m.release();
  });
}
void close_model(nsf_mlp_model* model) {
  delete model;
}

int record(const nsf_mlp_model* m, unsigned char* out, size_t capacity, size_t* size,
           nsf_mlp_error* error) {
  return guarded(error, [&] {
    const std::string bytes = nsf::encode_model_record(m->fields.record());
    *size = bytes.size();
    if (!out) return;
    if (capacity < bytes.size())
      nsf::fail("the record has ", bytes.size(), " bytes, the buffer ", capacity);
    std::memcpy(out, bytes.data(), bytes.size());
  });
}

int encoder_kind(const nsf_mlp_model* m, char* out, size_t capacity, nsf_mlp_error* error) {
  return guarded(error, [&] {
    const std::string& kind = m->net().encoder_kind();
    if (capacity == 0) nsf::fail("no room for the encoder's kind");
    const size_t n = std::min(kind.size(), capacity - 1);
    std::memcpy(out, kind.data(), n);
    out[n] = '\0';
  });
}

void set_threads(int threads) {
  if (threads > 0) nsf::set_nn_threads(threads, /*retain_memory=*/false);
}

int encode(const nsf_mlp_model* m, const double* x, size_t frames, size_t particles, double* z,
           nsf_mlp_error* error) {
  return guarded(error, [&] {
    std::vector<std::vector<Vec3>> in(frames, std::vector<Vec3>(particles));
    for (size_t f = 0; f < frames; ++f)
      for (size_t p = 0; p < particles; ++p) in[f][p] = Vec3(x + 3 * (f * particles + p));
    const std::vector<Eigen::VectorXd> out = m->net().encode(in);
    for (size_t f = 0; f < frames; ++f)
      std::copy(out[f].data(), out[f].data() + m->r(), z + f * size_t(m->r()));
  });
}

int prepare(const nsf_mlp_model* m, const double* X, size_t count, nsf_mlp_points** points,
            nsf_mlp_error* error) {
  return guarded(error, [&] {
    std::vector<Vec3> at(count);
    for (size_t p = 0; p < count; ++p) at[p] = Vec3(X + 3 * p);
    auto p = std::make_unique<nsf_mlp_points>();
    p->points = m->net().prepare(at);
    *points = p.release();
  });
}
void free_points(nsf_mlp_points* points) {
  delete points;
}

int deform(const nsf_mlp_model* m, const nsf_mlp_points* points, const uint32_t* ids, size_t n,
           const double* z, size_t latents, double* x, nsf_mlp_error* error) {
  return guarded(error, [&] {
    std::vector<Eigen::VectorXd> zs;
    for (size_t k = 0; k < latents; ++k) zs.push_back(latent(m, z + k * size_t(m->r())));
    std::vector<const Eigen::VectorXd*> at;
    for (const Eigen::VectorXd& v : zs) at.push_back(&v);
    const std::vector<uint32_t> list = ids ? id_list(ids, n) : std::vector<uint32_t>();
    std::vector<Vec3> out;
    m->net().deform(*points->points, ids ? &list : nullptr, at, out);
    put(out, n * latents, x);
  });
}

int stress(const nsf_mlp_model* m, const nsf_mlp_points* points, const uint32_t* ids, size_t n,
           const double* z, double mu, double* tau, nsf_mlp_error* error) {
  return guarded(error, [&] {
    const std::vector<uint32_t> list = ids ? id_list(ids, n) : std::vector<uint32_t>();
    std::vector<Mat3> out;
    m->net().stress(*points->points, ids ? &list : nullptr, latent(m, z), mu, out);
    put(out, n, tau);
  });
}

int affine(const nsf_mlp_model* m, const nsf_mlp_points* points, const uint32_t* ids, size_t n,
           const double* z, double* C, nsf_mlp_error* error) {
  return guarded(error, [&] {
    const std::vector<uint32_t> list = ids ? id_list(ids, n) : std::vector<uint32_t>();
    std::vector<Mat3> out;
    m->net().affine(*points->points, ids ? &list : nullptr, latent(m, z), out);
    put(out, n, C);
  });
}

int deformation_gradients(const nsf_mlp_model* m, const nsf_mlp_points* points, const uint32_t* ids,
                          size_t n, const double* z, double* F, nsf_mlp_error* error) {
  return guarded(error, [&] {
    std::vector<Mat3> out;
    m->net().deformation_gradients(*points->points, id_list(ids, n), latent(m, z), out);
    put(out, n, F);
  });
}

int samples(const nsf_mlp_model* m, const nsf_mlp_points* points, const uint32_t* ids, size_t n,
            nsf_mlp_samples** out, nsf_mlp_error* error) {
  return guarded(error, [&] {
    auto s = std::make_unique<nsf_mlp_samples>();
    s->g = m->net().samples(*points->points, id_list(ids, n));
    s->r = m->r();
    s->n = n;
    *out = s.release();
  });
}
void free_samples(nsf_mlp_samples* samples) {
  delete samples;
}

int sample_values(nsf_mlp_samples* s, const double* z, double* g, nsf_mlp_error* error) {
  return guarded(error, [&] {
    std::vector<Vec3> out;
    s->g->evaluate(Eigen::Map<const Eigen::VectorXd>(z, s->r), out);
    put(out, s->n, g);
  });
}

int sample_jacobian(nsf_mlp_samples* s, const double* z, double* J, double* g,
                    nsf_mlp_error* error) {
  return guarded(error, [&] {
    Eigen::MatrixXd jac;
    std::vector<Vec3> out;
    s->g->jacobian(Eigen::Map<const Eigen::VectorXd>(z, s->r), jac, out);
    if (jac.rows() != Eigen::Index(3 * s->n) || jac.cols() != s->r)
      nsf::fail("the Jacobian is ", jac.rows(), " x ", jac.cols(), ", not ", 3 * s->n, " x ", s->r);
    std::copy(jac.data(), jac.data() + jac.size(), J);
    put(out, s->n, g);
  });
}

const nsf_mlp_plugin kTable = {NSF_MLP_PLUGIN_ABI_VERSION,
                               sizeof(nsf_mlp_plugin),
                               NSF_VERSION,
                               open_model,
                               close_model,
                               record,
                               encoder_kind,
                               set_threads,
                               encode,
                               prepare,
                               free_points,
                               deform,
                               stress,
                               affine,
                               deformation_gradients,
                               samples,
                               free_samples,
                               sample_values,
                               sample_jacobian};

}  // namespace

extern "C" __attribute__((visibility("default"))) const nsf_mlp_plugin* nsf_mlp_plugin_table(void) {
  return &kTable;
}
