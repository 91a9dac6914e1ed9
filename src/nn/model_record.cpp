#include "nn/model_record.h"

#include <array>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string_view>
#include <utility>

#include "core/crc32.h"
#include "core/error.h"
#include "nn/checked_bytes.h"
#include "nn/zip_entries.h"

namespace nsf {

namespace {

constexpr char kMagic[8] = {'N', 'S', 'F', 'R', 'T', 'R', 'E', 'C'};
// 2: the attachments (ModelAttachments) in place of version 1's four numbers of the ROM's
// calibration, which a version 2 reader takes as the ROM's attachment (adopt_legacy_entries).
constexpr uint32_t kVersion = 2;
constexpr uint32_t kFirstVersionRead = 1;
// Version 1's four numbers, by the names the archive gave them, and whether 0 was a value (the
// archive stored each only where it was one; the record, -1 where none).
constexpr std::pair<const char*, bool> kLegacyNumbers[4] = {{"latent_prior", true},
                                                            {"calibrated_dt_ratio", false},
                                                            {"tracked_latent_prior", true},
                                                            {"tracked_calibrated_dt_ratio", false}};
// The attachment that the entries of files of format versions 1-8 (run-time record version 1)
// belong to: the ROM's calibration (rom/calibration/rom_calibration.h).
constexpr const char* kLegacyAttachment = "rom_calibration";
constexpr size_t kHeader = sizeof(kMagic) + 4 + 8 + 4;  // magic, version, size, CRC-32

static_assert(sizeof(double) == 8 && sizeof(float) == 4, "IEEE-754 floats");

// Little-endian fields, as every CPU nsf builds for stores them (x86-64, AArch64).
class Writer {
 public:
  template <typename T>
  void put(T v) {
    out_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void put_bytes(const void* p, size_t n) { out_.append(static_cast<const char*>(p), n); }
  void string(const std::string& s) { put<uint64_t>(s.size()), put_bytes(s.data(), s.size()); }
  template <typename T>
  void array(const T* p, size_t n) {
    put<uint64_t>(n), put_bytes(p, n * sizeof(T));
  }
  void vector(const Eigen::VectorXd& v) { array(v.data(), size_t(v.size())); }
  void matrix(const Eigen::MatrixXd& m) {  // rows, cols, then row-major values
    put<uint64_t>(uint64_t(m.rows())), put<uint64_t>(uint64_t(m.cols()));
    const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> r = m;
    put_bytes(r.data(), size_t(r.size()) * sizeof(double));
  }
  std::string& bytes() { return out_; }

 private:
  std::string out_;
};

class Reader {
 public:
  Reader(std::string_view b, size_t at, const std::string& path) : b_(b), at_(at), path_(path) {}
  template <typename T>
  T get() {
    T v;
    std::memcpy(&v, take(sizeof v), sizeof v);
    return v;
  }
  std::string string() {
    const uint64_t n = count(1);
    return std::string(take(n), n);
  }
  template <typename T>
  std::vector<T> array() {
    const uint64_t n = count(sizeof(T));
    std::vector<T> v(n);
    if (n) std::memcpy(v.data(), take(n * sizeof(T)), n * sizeof(T));
    return v;
  }
  Eigen::VectorXd vector() {
    const std::vector<double> v = array<double>();
    return Eigen::Map<const Eigen::VectorXd>(v.data(), Eigen::Index(v.size()));
  }
  Eigen::MatrixXd matrix() {
    const uint64_t rows = get<uint64_t>(), cols = get<uint64_t>();
    if (cols != 0 && rows > (b_.size() - at_) / 8 / cols) bad("a matrix runs past its end");
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> m(rows, cols);
    if (m.size()) std::memcpy(m.data(), take(size_t(m.size()) * 8), size_t(m.size()) * 8);
    return m;
  }
  bool done() const { return at_ == b_.size(); }
  [[noreturn]] void bad(const std::string& why) const {
    fail("model file ", path_, ": its run-time record is damaged (", why,
         "); copy the file again or save it anew with nsf train");
  }

 private:
  const char* take(uint64_t n) {
    if (n > b_.size() - at_) bad("it is cut short");
    const char* p = b_.data() + at_;
    at_ += n;
    return p;
  }
  uint64_t count(size_t size) {  // an element count that must fit in what is left
    const uint64_t n = get<uint64_t>();
    if (n > (b_.size() - at_) / size) bad("a length runs past its end");
    return n;
  }
  std::string_view b_;
  size_t at_;
  const std::string& path_;
};

void put_net(Writer& w, const CoefficientNet& net) {
  w.put<uint32_t>(uint32_t(net.W.size()));
  for (size_t i = 0; i < net.W.size(); ++i) w.matrix(net.W[i]), w.vector(net.b[i]);
  w.vector(net.in_shift), w.vector(net.in_scale), w.vector(net.out_scale);
}

CoefficientNet get_net(Reader& r) {
  CoefficientNet net;
  const uint32_t layers = r.get<uint32_t>();
  if (layers > 64) r.bad("too many layers");
  for (uint32_t i = 0; i < layers; ++i) {
    net.W.push_back(r.matrix());
    net.b.push_back(r.vector());
    if (net.b.back().size() != net.W.back().rows() ||
        (i > 0 && net.W[i].cols() != net.W[i - 1].rows()))
      r.bad("a coefficient network's layers do not fit together");
  }
  net.in_shift = r.vector(), net.in_scale = r.vector(), net.out_scale = r.vector();
  if (!net.W.empty() &&
      (net.in_shift.size() != net.inputs() || net.in_scale.size() != net.inputs() ||
       net.out_scale.size() != net.outputs()))
    r.bad("a coefficient network's scales do not fit its layers");
  return net;
}

void put_basis(Writer& w, const PointBasis& b) {
  w.put<int32_t>(b.dim), w.put<int32_t>(b.K), w.put<uint64_t>(b.points);
  w.array(b.mean.data(), b.mean.size()), w.array(b.modes.data(), b.modes.size());
  put_net(w, b.net);
  w.put<uint8_t>(!b.map.empty());
  if (!b.map.empty()) {
    w.matrix(b.map.centers), w.matrix(b.map.weights), w.matrix(b.map.poly);
    w.vector(b.map.shift), w.vector(b.map.scale), w.put<double>(b.map.smoothing);
  }
}

PointBasis get_basis(Reader& r, int dim, size_t points, int latent_inputs) {
  PointBasis b;
  b.dim = r.get<int32_t>(), b.K = r.get<int32_t>();
  b.points = r.get<uint64_t>();
  if (b.dim != dim || b.points != points || b.K < 1) r.bad("a basis has the wrong shape");
  b.mean = r.array<float>(), b.modes = r.array<float>();
  if (b.mean.size() != points * size_t(dim) || b.modes.size() != b.mean.size() * size_t(b.K))
    r.bad("a basis's values do not fit its shape");
  b.net = get_net(r);
  if (r.get<uint8_t>()) {
    b.map.centers = r.matrix(), b.map.weights = r.matrix(), b.map.poly = r.matrix();
    b.map.shift = r.vector(), b.map.scale = r.vector(), b.map.smoothing = r.get<double>();
    const Eigen::Index d = b.map.centers.cols();
    if (b.map.weights.rows() != b.map.centers.rows() || b.map.weights.cols() != b.K ||
        b.map.poly.rows() != d + 1 || b.map.poly.cols() != b.K || b.map.shift.size() != d ||
        b.map.scale.size() != d)
      r.bad("a coefficient map's parts do not fit together");
  } else if (b.net.W.empty() || b.net.outputs() != b.K || b.net.inputs() < latent_inputs) {
    r.bad("a basis has no coefficients that fit it");
  }
  return b;
}

}  // namespace

std::string encode_model_record(const ModelRecord& m) {
  Writer w;
  w.string(m.scene.scene_name), w.put<int64_t>(m.scene.particles), w.put<uint64_t>(m.scene.x_hash);
  w.put<uint8_t>(uint8_t(m.family)), w.put<int32_t>(m.latent_dim);
  w.put<uint8_t>(m.stress_uses_mu);
  w.put<double>(m.mu_min), w.put<double>(m.mu_max);
  w.string(m.training_box.to_json().dump()), w.put<double>(m.train_seconds);
  w.put<uint64_t>(m.attachments.size());
  for (const auto& [name, text] : m.attachments) w.string(name), w.string(text);
  w.vector(m.latent_spread);
  w.put<uint64_t>(m.trajectory_latents.size());
  w.put<uint64_t>(m.trajectory_latents.empty() ? 0 : m.trajectory_latents[0].size());
  for (const auto& run : m.trajectory_latents)
    for (const Eigen::VectorXd& z : run) w.put_bytes(z.data(), size_t(z.size()) * sizeof(double));
  w.array(m.trajectory_mu.data(), m.trajectory_mu.size());
  w.vector(m.rest_latent);
  w.put<uint8_t>(m.bases != nullptr);
  if (m.bases) {
    const BasisDecoders& d = *m.bases;
    w.put<uint8_t>(d.stress_uses_mu), w.put<uint8_t>(d.affine_uses_velocity);
    w.put<uint8_t>(d.stress_uses_velocity);
    w.array(d.rest.empty() ? nullptr : d.rest[0].data(), 3 * d.rest.size());
    put_basis(w, d.u), put_basis(w, d.tau), put_basis(w, d.C);
  }
  std::string out;
  const std::string& payload = w.bytes();
  out.reserve(kHeader + payload.size());
  out.append(kMagic, sizeof kMagic);
  const uint32_t version = kVersion, crc = crc32_of(payload.data(), payload.size());
  const uint64_t size = payload.size();
  out.append(reinterpret_cast<const char*>(&version), 4);
  out.append(reinterpret_cast<const char*>(&size), 8);
  out.append(reinterpret_cast<const char*>(&crc), 4);
  return out.append(payload);
}

bool is_model_record(const char* p, size_t n) {
  return n >= kHeader && std::memcmp(p, kMagic, sizeof kMagic) == 0;
}

ModelRecord decode_model_record(std::string_view bytes, const std::string& path) {
  Reader head(bytes, 0, path);
  if (!is_model_record(bytes.data(), bytes.size())) head.bad("no record header");
  head.get<std::array<char, 8>>();
  const uint32_t version = head.get<uint32_t>();
  const uint64_t size = head.get<uint64_t>();
  const uint32_t crc = head.get<uint32_t>();
  if (version < kFirstVersionRead || version > kVersion)
    fail("model file ", path, ": its run-time record has version ", version, "; this nsf reads ",
         kFirstVersionRead, " to ", kVersion,
         ": use the nsf that wrote it, or save the model anew");
  if (size != bytes.size() - kHeader) head.bad("its length does not match");
  if (crc32_of(bytes.data() + kHeader, size) != crc) head.bad("its CRC-32 does not match");
  Reader r(bytes, kHeader, path);
  ModelRecord m;
  m.scene.scene_name = r.string();
  m.scene.particles = r.get<int64_t>(), m.scene.x_hash = r.get<uint64_t>();
  const uint8_t family = r.get<uint8_t>();
  if (family > uint8_t(DecoderFamily::mlp)) r.bad("an unknown decoder family");
  m.family = DecoderFamily(family);
  m.latent_dim = r.get<int32_t>();
  if (m.latent_dim < 1 || m.latent_dim > 4096 || m.scene.particles < 1 ||
      uint64_t(m.scene.particles) > bytes.size())
    r.bad("bad sizes");
  m.stress_uses_mu = r.get<uint8_t>();
  m.mu_min = r.get<double>(), m.mu_max = r.get<double>();
  const std::string box = r.string();
  try {
    m.training_box = TrainingBox::from_json(nlohmann::json::parse(box), "model file " + path);
  } catch (const nlohmann::json::exception&) {
    r.bad("its training box is not JSON");
  }
  m.train_seconds = r.get<double>();
  if (version == 1) {
    nlohmann::json entries = nlohmann::json::object();
    for (const auto& [key, zero_is_value] : kLegacyNumbers)
      if (const double v = r.get<double>(); v > 0 || (zero_is_value && v == 0)) entries[key] = v;
    adopt_legacy_entries(m.attachments, entries);
  } else {
    const uint64_t n = r.get<uint64_t>();
    for (uint64_t i = 0; i < n; ++i) {
      std::string name = r.string();
      m.attachments[name] = r.string();
    }
  }
  const Eigen::Index dim = m.latent_dim;
  m.latent_spread = r.vector();
  if (m.latent_spread.size() != dim) r.bad("the latent spread has the wrong size");
  const uint64_t runs = r.get<uint64_t>(), frames = r.get<uint64_t>();
  if (runs > 0 && (frames == 0 || frames > (bytes.size() / 8) / uint64_t(dim) / runs))
    r.bad("the training latents run past its end");
  for (uint64_t i = 0; i < runs; ++i) {
    m.trajectory_latents.emplace_back();
    for (uint64_t k = 0; k < frames; ++k) {
      Eigen::VectorXd z(dim);
      for (Eigen::Index c = 0; c < dim; ++c) z[c] = r.get<double>();
      m.trajectory_latents.back().push_back(std::move(z));
    }
  }
  m.trajectory_mu = r.array<double>();
  if (m.trajectory_mu.size() != runs) r.bad("the training runs' μ do not match their latents");
  m.rest_latent = r.vector();
  if (m.rest_latent.size() != 0 && m.rest_latent.size() != dim)
    r.bad("the rest state's latent has the wrong size");
  if (r.get<uint8_t>()) {
    auto d = std::make_shared<BasisDecoders>();
    d->stress_uses_mu = r.get<uint8_t>(), d->affine_uses_velocity = r.get<uint8_t>();
    d->stress_uses_velocity = r.get<uint8_t>();
    const std::vector<double> rest = r.array<double>();
    const size_t P = size_t(m.scene.particles);
    if (rest.size() != 3 * P) r.bad("the rest positions do not match the particle count");
    d->rest.resize(P);
    for (size_t p = 0; p < P; ++p) d->rest[p] = Vec3(rest[3 * p], rest[3 * p + 1], rest[3 * p + 2]);
    d->u = get_basis(r, 3, P, int(dim));
    d->tau = get_basis(r, 6, P, int(dim));
    d->C = get_basis(r, 9, P, int(dim));
    m.bases = std::move(d);
  }
  if (m.family == DecoderFamily::basis && !m.bases) r.bad("a basis model without its bases");
  if (!r.done()) r.bad("bytes are left over");
  return m;
}

void adopt_legacy_entries(ModelAttachments& attachments, const nlohmann::json& entries) {
  if (!entries.empty()) attachments.emplace(kLegacyAttachment, entries.dump());
}

std::optional<ModelRecord> find_model_record(const std::string& path) {
  bool checked = false;
  const std::string bytes = read_checked_file(path, "model file", checked);
  std::vector<ZipEntry> entries;
  zip_directory(bytes, checked ? checksum_comment_length() : 0, "model file", path, entries);
  for (const ZipEntry& e : entries) {
    if (e.method != 0 || !is_model_record(bytes.data() + e.data, e.size)) continue;
    if (!checked)
      fail("model file ", path,
           " is damaged: nsf wrote it with a checksum, and it has none now (bytes were appended "
           "or cut, or its zip comment was removed). Copy it again or retrain");
    return decode_model_record(std::string_view(bytes).substr(size_t(e.data), e.size), path);
  }
  return std::nullopt;
}

ModelRecord read_model_record(const std::string& path) {
  if (std::optional<ModelRecord> record = find_model_record(path)) return std::move(*record);
  fail("model file ", path,
       " has no run-time record, which this torch-free runtime needs: it is an MLP model (its "
       "networks need LibTorch: run it with the nsf tool), or a basis model saved by an older "
       "nsf (rewrite it with `nsf upgrade ",
       path, "`)");
}

}  // namespace nsf
