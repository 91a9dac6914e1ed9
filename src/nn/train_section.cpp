#include "nn/train_section.h"

#include <cmath>
#include <sstream>

#include "core/error.h"
#include "core/json_util.h"

namespace nsf {

namespace {

// The string at `key`, which must be `a` or `b`; "" when absent.
std::string one_of(const nlohmann::json& train, const std::string& path, const char* key,
                   const char* a, const char* b) {
  if (!train.contains(key)) return "";
  const nlohmann::json& v = train.at(key);
  if (!v.is_string() || (v.get<std::string>() != a && v.get<std::string>() != b))
    fail("scene: '", json::child(path, key), "' must be \"", a, "\" or \"", b, "\", got ",
         v.dump());
  return v.get<std::string>();
}

// Three positive integers, each at most `hi`.
template <typename T>
std::array<T, 3> positive_triple(const nlohmann::json& j, const std::string& path, long hi) {
  if (!j.is_array() || j.size() != 3)
    fail("scene: '", path, "' must be an array of three positive integers, got ", j.dump());
  std::array<T, 3> out{};
  for (size_t i = 0; i < 3; ++i) {
    if (!j[i].is_number_integer() || j[i].get<long>() < 1 || j[i].get<long>() > hi)
      fail("scene: '", json::child(path, i), "' must be an integer in [1, ", hi, "], got ",
           j[i].dump());
    out[i] = T(j[i].get<long>());
  }
  return out;
}

}  // namespace

TrainSection parse_train_section(const nlohmann::json& train, const std::string& path) {
  json::require_object(train, path);
  // "calibrate" is the ROM's (rom/calibration/calibration_recipe.h).
  json::check_keys(train, path,
                   {"steps", "widths", "encoder_max_length", "latent_dim", "decoder", "encoder",
                    "frames_per_batch", "particles_per_frame", "calibrate"});
  TrainSection t;
  if (train.contains("steps"))
    t.steps = positive_triple<long>(train.at("steps"), json::child(path, "steps"), 100000000);
  if (train.contains("widths"))
    t.widths = positive_triple<int>(train.at("widths"), json::child(path, "widths"), 4096);
  for (auto [key, out] : {std::pair{"frames_per_batch", &t.frames_per_batch},
                          std::pair{"particles_per_frame", &t.particles_per_frame}})
    if (train.contains(key))
      *out = positive_triple<int>(train.at(key), json::child(path, key), 1 << 20);
  t.encoder_max_length = json::get_int(train, path, "encoder_max_length", 0, 0, 1 << 20);
  if (t.encoder_max_length > 0 && t.encoder_max_length < 5)
    fail("scene: '", json::child(path, "encoder_max_length"),
         "' must be at least 5 (the convolution kernel is 6), or 0 for App. E's, got ",
         t.encoder_max_length);
  t.latent_dim = json::get_int(train, path, "latent_dim", 0, 1, 1024);
  t.decoder = one_of(train, path, "decoder", "mlp", "basis");
  t.encoder = one_of(train, path, "encoder", "network", "modes");
  return t;
}

TrainPlan with_train_section(TrainPlan plan, const TrainSection& section,
                             const GivenOnCommandLine& given) {
  if (section.steps && !given.steps) plan.steps = *section.steps;
  for (size_t n = 0; n < 3; ++n)
    if (section.widths && !given.widths[n]) plan.widths[n] = (*section.widths)[n];
  if (section.encoder_max_length > 0 && !given.encoder_max_length)
    plan.encoder_max_length = section.encoder_max_length;
  if (section.latent_dim > 0 && !given.latent_dim) plan.latent_dim = section.latent_dim;
  if (!section.decoder.empty() && !given.decoder) plan.decoder = section.decoder;
  if (!section.encoder.empty() && !given.encoder) plan.encoder = section.encoder;
  if (section.frames_per_batch && !given.frames_per_batch)
    plan.frames_per_batch = *section.frames_per_batch;
  if (section.particles_per_frame && !given.particles_per_frame)
    plan.particles_per_frame = *section.particles_per_frame;
  return plan;
}

std::string recipe_taken(const TrainSection& section, const GivenOnCommandLine& given) {
  std::ostringstream out;
  const auto triple = [&](const char* name, const auto& v) {
    out << name << " " << v[0] << "," << v[1] << "," << v[2] << "; ";
  };
  if (section.steps && !given.steps) triple("steps", *section.steps);
  const char network[] = "ghl";
  for (size_t n = 0; n < 3; ++n)
    if (section.widths && !given.widths[n])
      out << "width " << network[n] << " " << (*section.widths)[n] << "; ";
  if (section.encoder_max_length > 0 && !given.encoder_max_length)
    out << "encoder_max_length " << section.encoder_max_length << "; ";
  if (section.latent_dim > 0 && !given.latent_dim) out << "r " << section.latent_dim << "; ";
  if (!section.decoder.empty() && !given.decoder) out << "decoder " << section.decoder << "; ";
  if (!section.encoder.empty() && !given.encoder) out << "encoder " << section.encoder << "; ";
  if (section.frames_per_batch && !given.frames_per_batch)
    triple("frames_per_batch", *section.frames_per_batch);
  if (section.particles_per_frame && !given.particles_per_frame)
    triple("particles_per_frame", *section.particles_per_frame);
  std::string text = out.str();
  return text.empty() ? text : text.substr(0, text.size() - 2);
}

}  // namespace nsf
