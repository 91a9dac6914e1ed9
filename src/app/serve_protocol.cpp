#include "app/serve_protocol.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/error.h"
#include "nn/basis_decoders.h"

namespace nsf::app {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the stream's layout is little-endian");

namespace {

template <typename T>
void put(std::string& out, T v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}
template <typename T>
bool get(const std::string& in, size_t& at, T& v) {
  if (in.size() < at + sizeof v) return false;
  std::memcpy(&v, in.data() + at, sizeof v);
  at += sizeof v;
  return true;
}

}  // namespace

std::string model_message(const BasisDecoders& b, const nlohmann::json& info, int modes_here,
                          const std::vector<int>& rigid_frame) {
  const size_t P = b.rest.size();
  const int K = b.u.K;
  if (modes_here < 0 || modes_here > K) fail("model_message: ", modes_here, " of ", K, " modes");
  if (!rigid_frame.empty() && rigid_frame.size() != P)
    fail("model_message: rigid frames of ", rigid_frame.size(), " particles, the basis has ", P);
  std::vector<float> rest(3 * P), leading(3 * P * size_t(modes_here));
  for (size_t p = 0; p < P; ++p)
    for (int k = 0; k < 3; ++k) rest[3 * p + size_t(k)] = float(b.rest[p][k]);
  for (size_t row = 0; row < 3 * P; ++row)
    std::copy_n(&b.u.modes[row * size_t(K)], modes_here, &leading[row * size_t(modes_here)]);
  const std::vector<float> frame(rigid_frame.begin(), rigid_frame.end());
  std::vector<std::pair<std::string, const std::vector<float>*>> arrays = {
      {"rest", &rest}, {"mean", &b.u.mean}, {"modes", &leading}};
  if (!frame.empty()) arrays.push_back({"frame", &frame});
  nlohmann::json h = info;
  h["rigid_frames"] =
      rigid_frame.empty() ? 0 : *std::max_element(rigid_frame.begin(), rigid_frame.end()) + 1;
  h["type"] = "model";
  h["version"] = 2;
  h["particles"] = P;
  h["modes"] = K;
  h["modes_here"] = modes_here;
  h["positions"] = "x_p = rest_p + mean_p + modes_p c  (modes_p: 3 x K, row-major)";
  // The offsets depend on the header's length, which depends on the offsets' digits: lay out
  // with a generous header size, then pad the JSON to it.
  std::string text;
  size_t header_bytes = 0;
  for (int pass = 0; pass < 2; ++pass) {
    size_t offset = 8 + header_bytes;
    h["arrays"] = nlohmann::json::array();
    for (const auto& [name, v] : arrays) {
      nlohmann::json shape = name == "modes"   ? nlohmann::json{P, 3, modes_here}
                             : name == "frame" ? nlohmann::json{P}
                                               : nlohmann::json{P, 3};
      h["arrays"].push_back({{"name", name}, {"offset", offset}, {"shape", shape}});
      offset += v->size() * sizeof(float);
    }
    text = h.dump();
    if (header_bytes >= text.size()) break;
    header_bytes = (text.size() + 64 + 3) / 4 * 4;
  }
  text.resize(header_bytes, ' ');
  std::string out = "NSFM";
  put(out, uint32_t(header_bytes));
  out += text;
  for (const auto& [name, v] : arrays)
    out.append(reinterpret_cast<const char*>(v->data()), v->size() * sizeof(float));
  return out;
}

std::string basis_message(const BasisDecoders& b, int first, int count) {
  const size_t P = b.rest.size(), K = size_t(b.u.K);
  if (first < 0 || count < 1 || size_t(first + count) > K)
    fail("basis_message: modes ", first, " + ", count, " of ", K);
  std::string out = "NSFB";
  out.reserve(kBasisHeaderBytes + 12 * P * size_t(count));
  put(out, uint32_t(first));
  put(out, uint32_t(count));
  put(out, uint32_t(P));
  for (size_t row = 0; row < 3 * P; ++row)
    out.append(reinterpret_cast<const char*>(&b.u.modes[row * K + size_t(first)]),
               size_t(count) * sizeof(float));
  return out;
}

StreamPose stream_pose(const Vec3& position, const Mat3& rotation) {
  StreamPose p;
  for (int k = 0; k < 3; ++k) p[size_t(k)] = float(position[k]);
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) p[size_t(3 + 3 * r + k)] = float(rotation(r, k));
  return p;
}

int modes_per_message(size_t particles, size_t bytes) {
  return int(std::clamp<size_t>(bytes / std::max<size_t>(1, 12 * particles), 1, 1 << 20));
}

std::string frame_message(uint32_t frame, double time, double sent, const Eigen::VectorXd& z,
                          const Eigen::VectorXf& c, const std::vector<StreamPose>& poses,
                          float indicator, const std::vector<StreamPose>& rigid) {
  std::string out = "NSFF";
  out.reserve(kFrameHeaderBytes + 8 * size_t(z.size()) + 4 * size_t(c.size()) +
              48 * (poses.size() + rigid.size()));
  put(out, frame);
  put(out, time);
  put(out, sent);
  put(out, uint32_t(z.size()));
  put(out, uint32_t(c.size()));
  put(out, uint32_t(poses.size()));
  put(out, indicator);
  for (Eigen::Index i = 0; i < z.size(); ++i) put(out, z[i]);
  for (Eigen::Index i = 0; i < c.size(); ++i) put(out, c[i]);
  for (const std::vector<StreamPose>* list : {&poses, &rigid})
    for (const StreamPose& p : *list)
      for (float v : p) put(out, v);
  return out;
}

std::optional<StreamModel> decode_model(const std::string& bytes) {
  if (bytes.compare(0, 4, "NSFM") != 0) return std::nullopt;
  size_t at = 4;
  uint32_t hb = 0;
  if (!get(bytes, at, hb) || bytes.size() < at + hb) return std::nullopt;
  StreamModel m;
  try {
    m.header = nlohmann::json::parse(bytes.substr(at, hb));
    m.K = m.header.at("modes").get<int>();
    m.received = m.header.value("modes_here", m.K);
    // At most 2^16 modes: the header alone cannot make the client hold a basis of any size.
    if (m.K < 0 || m.K > (1 << 16) || m.received < 0 || m.received > m.K) return std::nullopt;
    std::vector<float> leading;
    for (const auto& a : m.header.at("arrays")) {
      size_t n = 1;
      for (const auto& d : a.at("shape")) n *= d.get<size_t>();
      const size_t off = a.at("offset").get<size_t>();
      if (off + 4 * n > bytes.size()) return std::nullopt;
      std::vector<float> v(n);
      std::memcpy(v.data(), bytes.data() + off, 4 * n);
      const std::string name = a.at("name");
      (name == "rest"    ? m.rest
       : name == "mean"  ? m.mean
       : name == "frame" ? m.frame
                         : leading) = std::move(v);
    }
    const size_t rows = m.rest.size(), K = size_t(m.K), here = size_t(m.received);
    if (rows % 3 != 0 || m.mean.size() != rows || leading.size() != rows * here ||
        (!m.frame.empty() && 3 * m.frame.size() != rows))
      return std::nullopt;
    const int frames = m.header.value("rigid_frames", 0);
    for (float k : m.frame)  // a frame index the frame messages will carry, or −1
      if (!(k == -1 || (k >= 0 && k < float(frames) && k == std::floor(k)))) return std::nullopt;
    m.modes.assign(rows * K, 0.0f);
    for (size_t row = 0; row < rows; ++row)
      std::copy_n(&leading[row * here], here, &m.modes[row * K]);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  return m;
}

std::optional<StreamFrame> decode_frame(const std::string& bytes) {
  if (bytes.compare(0, 4, "NSFF") != 0) return std::nullopt;
  size_t at = 4;
  StreamFrame f;
  uint32_t r = 0, K = 0, nc = 0;
  if (!get(bytes, at, f.frame) || !get(bytes, at, f.time) || !get(bytes, at, f.sent) ||
      !get(bytes, at, r) || !get(bytes, at, K) || !get(bytes, at, nc) ||
      !get(bytes, at, f.indicator))
    return std::nullopt;
  // The rigid frames' maps fill the rest: whole poses, however many.
  const size_t fixed = kFrameHeaderBytes + 8 * size_t(r) + 4 * size_t(K) + 48 * size_t(nc);
  if (bytes.size() < fixed || (bytes.size() - fixed) % 48 != 0) return std::nullopt;
  f.z.resize(r);
  f.c.resize(K);
  f.poses.resize(nc);
  f.rigid.resize((bytes.size() - fixed) / 48);
  for (double& v : f.z) get(bytes, at, v);
  for (float& v : f.c) get(bytes, at, v);
  for (std::vector<StreamPose>* list : {&f.poses, &f.rigid})
    for (StreamPose& p : *list)
      for (float& v : p) get(bytes, at, v);
  return f;
}

bool add_basis(StreamModel& m, const std::string& bytes) {
  if (bytes.compare(0, 4, "NSFB") != 0) return false;
  size_t at = 4;
  uint32_t first = 0, n = 0, P = 0;
  if (!get(bytes, at, first) || !get(bytes, at, n) || !get(bytes, at, P)) return false;
  const size_t rows = m.rest.size(), K = size_t(m.K);
  if (first != uint32_t(m.received) || n == 0 || size_t(first) + n > K || 3 * size_t(P) != rows ||
      bytes.size() != kBasisHeaderBytes + 4 * rows * n)
    return false;
  for (size_t row = 0; row < rows; ++row)
    std::memcpy(&m.modes[row * K + first], bytes.data() + at + 4 * row * n, 4 * size_t(n));
  m.received += int(n);
  return true;
}

std::vector<float> reconstruct(const StreamModel& m, const std::vector<float>& c,
                               const std::vector<StreamPose>& rigid) {
  const size_t P = m.rest.size() / 3, K = size_t(m.K);
  std::vector<float> x(3 * P);
  for (size_t p = 0; p < P; ++p) {
    for (size_t d = 0; d < 3; ++d) {
      const float* B = &m.modes[(3 * p + d) * K];
      float acc = 0;
      for (size_t k = 0; k < K; ++k) acc += B[k] * c[k];
      x[3 * p + d] = m.rest[3 * p + d] + (m.mean[3 * p + d] + acc);
    }
    const int f = m.frame.empty() ? -1 : int(m.frame[p]);
    if (f < 0 || size_t(f) >= rigid.size()) continue;  // no frame, or none streamed yet
    const StreamPose& T = rigid[size_t(f)];
    const float y[3] = {x[3 * p], x[3 * p + 1], x[3 * p + 2]};
    for (size_t d = 0; d < 3; ++d)
      x[3 * p + d] = T[d] + (T[3 + 3 * d] * y[0] + T[4 + 3 * d] * y[1] + T[5 + 3 * d] * y[2]);
  }
  return x;
}

ServeCommand parse_command(const std::string& text, size_t collider_count) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const std::exception&) {
    fail("a command that is not JSON");
  }
  if (!j.is_object() || !j.contains("type") || !j["type"].is_string())
    fail("a command without a \"type\"");
  const std::string type = j["type"];
  const auto numbers = [&](const char* key, size_t n) {
    const nlohmann::json& v = j[key];
    if (!v.is_array() || v.size() != n) fail("\"", key, "\" is not a list of ", n, " numbers");
    std::vector<double> out;
    for (const auto& e : v) {
      if (!e.is_number() || !std::isfinite(e.get<double>()))
        fail("\"", key, "\" holds something other than a finite number");
      out.push_back(e.get<double>());
    }
    return out;
  };
  ServeCommand c;
  if (type == "reset") {
    if (j.size() != 1) fail("a reset command takes no other keys");
    c.kind = ServeCommand::reset;
    return c;
  }
  if (type != "move") fail("an unknown command type '", type.substr(0, 40), "'");
  for (const auto& [k, v] : j.items())
    if (k != "type" && k != "collider" && k != "position" && k != "rotation")
      fail("an unknown key '", k.substr(0, 40), "' in a move command");
  if (!j.contains("collider") || !j["collider"].is_number_unsigned() ||
      j["collider"].get<uint64_t>() >= collider_count)
    fail("\"collider\" is not the index of one of the scene's ", collider_count, " colliders");
  c.collider = j["collider"].get<size_t>();
  if (!j.contains("position")) fail("a move command without a \"position\"");
  const auto x = numbers("position", 3);
  c.position = Vec3(x[0], x[1], x[2]);
  if (j.contains("rotation")) {
    const auto r = numbers("rotation", 9);
    Mat3 R;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) R(a, b) = r[size_t(3 * a + b)];
    if ((R.transpose() * R - Mat3::Identity()).norm() > 1e-4 || R.determinant() < 0)
      fail("\"rotation\" is not a rotation matrix (orthonormal, det +1)");
    c.rotation = R;
  }
  return c;
}

}  // namespace nsf::app
