#include "nn/model/model_file_checks.h"

#include <climits>
#include <map>
#include <sstream>
#include <vector>

#include "core/error.h"

namespace nsf {

namespace {

// float32 numbers in a fully connected network of `depth` hidden layers of `width`.
double mlp_numbers(double in, double out, double width, double depth) {
  return (in + 1) * width + (depth - 1) * (width + 1) * width + (width + 1) * out;
}

std::string shape_text(at::IntArrayRef s) {
  std::ostringstream os;
  os << s;
  return os.str();
}

}  // namespace

int model_size_entry(int64_t value, const std::string& key, const std::string& path) {
  if (value < 1 || value > INT_MAX)
    fail("model file ", path, ": damaged entry '", key, "' = ", value, " (a size, expected 1 to ",
         INT_MAX, ")");
  return static_cast<int>(value);
}

uint64_t model_hash_entry(const std::string& text, const std::string& path) {
  if (text.empty() || text.size() > 16 ||
      text.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos)
    fail("model file ", path, ": damaged entry 'scene_x_hash' = '", text.substr(0, 40),
         "' (expected up to 16 hex digits)");
  return std::stoull(text, nullptr, 16);
}

void check_model_fits_file(const NetConfig& c, int64_t particles, bool stress_uses_mu,
                           uintmax_t file_bytes, const std::string& path) {
  if (file_bytes == 0) return;
  const double r = c.latent_dim, mu = stress_uses_mu ? 1 : 0;
  // The encoder's last two layers, whatever its convolutions.
  double numbers = (c.encoder_hidden + 1.0) * (r + 1);
  if (c.decoder == DecoderFamily::basis) {
    const double dims[3] = {3, 6, 9};
    for (int f = 0; f < 3; ++f)
      numbers +=
          mlp_numbers(r + (f == 1 ? mu : 0), c.modes[f], c.coefficient_width, c.coefficient_depth) +
          double(particles) * dims[f] * (c.modes[f] + 1.0);
  } else {
    numbers += mlp_numbers(3 + r, 3, c.width_g, c.depth) +
               mlp_numbers(3 + r + mu, 6, c.width_h, c.depth) +
               mlp_numbers(3 + r, 9, c.width_l, c.depth);
  }
  if (numbers > double(file_bytes))
    fail("model file ", path, " is damaged: its sizes (r = ", c.latent_dim, ", depth ", c.depth,
         ", widths ", c.width_g, "/", c.width_h, "/", c.width_l, ", coefficient width ",
         c.coefficient_width, ", depth ", c.coefficient_depth, ", modes ", c.modes[0], "/",
         c.modes[1], "/", c.modes[2], ", ", particles, " particles) need ", numbers,
         " numbers, more than the file's ", file_bytes, " bytes hold");
}

void check_model_tensor(const torch::Tensor& t, at::IntArrayRef shape, const std::string& key,
                        const std::string& path) {
  if (!t.defined() || t.scalar_type() != torch::kFloat32 || t.sizes() != shape)
    fail("model file ", path, ": damaged entry '", key, "' (",
         t.defined() ? std::string(c10::toString(t.scalar_type())) + " " + shape_text(t.sizes())
                     : std::string("undefined"),
         ", expected Float ", shape_text(shape), ")");
  if (!torch::isfinite(t).all().item<bool>())
    fail("model file ", path, ": entry '", key, "' holds a NaN or infinite value");
}

void load_network_checked(torch::nn::Module& net, torch::serialize::InputArchive& archive,
                          const std::string& name, const std::string& path) {
  std::map<std::string, std::pair<std::vector<int64_t>, at::ScalarType>> built;
  for (const auto& p : net.named_parameters())
    built[p.key()] = {p.value().sizes().vec(), p.value().scalar_type()};
  for (const auto& b : net.named_buffers())
    built[b.key()] = {b.value().sizes().vec(), b.value().scalar_type()};
  net.load(archive);
  auto check = [&](const std::string& key, const torch::Tensor& t) {
    const auto& [shape, type] = built.at(key);
    if (t.sizes().vec() != shape || t.scalar_type() != type)
      fail("model file ", path, ": damaged network '", name, "': '", key, "' is ",
           c10::toString(t.scalar_type()), " ", shape_text(t.sizes()), ", the configuration needs ",
           c10::toString(type), " ", shape_text(shape));
    if (t.is_floating_point() && !torch::isfinite(t).all().item<bool>())
      fail("model file ", path, ": network '", name, "': '", key,
           "' holds a NaN or infinite weight");
  };
  for (const auto& p : net.named_parameters()) check(p.key(), p.value());
  for (const auto& b : net.named_buffers()) check(b.key(), b.value());
}

}  // namespace nsf
