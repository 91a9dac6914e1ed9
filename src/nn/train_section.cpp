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

// A non-empty array of finite numbers, each positive (or non-negative where zero is allowed),
// ascending where asked.
std::vector<double> numbers(const nlohmann::json& j, const std::string& path, bool zero_allowed,
                            bool ascending, const char* meaning) {
  if (!j.is_array() || j.empty())
    fail("scene: '", path, "' must be a non-empty array of numbers (", meaning, "), got ",
         j.dump());
  std::vector<double> out;
  for (size_t i = 0; i < j.size(); ++i) {
    const double v = j[i].is_number() ? j[i].get<double>() : -1;
    if (!j[i].is_number() || !std::isfinite(v) || v < 0 || (v == 0 && !zero_allowed) ||
        (ascending && !out.empty() && v <= out.back()))
      fail("scene: '", json::child(path, i), "' must be a ",
           zero_allowed ? "non-negative" : "positive", " number", ascending ? ", ascending" : "",
           " (", meaning, "), got ", j[i].dump());
    out.push_back(v);
  }
  return out;
}

CalibrationRecipe parse_calibration_recipe(const nlohmann::json& j, const std::string& path) {
  json::require_object(j, path);
  json::check_keys(j, path, {"grid", "dt_ratios", "set"});
  CalibrationRecipe c;
  if (j.contains("grid"))
    c.grid = numbers(j.at("grid"), json::child(path, "grid"), true, false,
                     "the latent prior lengths tried, metres");
  if (j.contains("dt_ratios"))
    c.dt_ratios = numbers(j.at("dt_ratios"), json::child(path, "dt_ratios"), false, true,
                          "the ROM steps tried over the scene's dt");
  if (j.contains("set")) {
    const nlohmann::json& s = j.at("set");
    if (!s.is_array())
      fail("scene: '", json::child(path, "set"), "' must be an array of KEY=VALUE");
    for (size_t i = 0; i < s.size(); ++i) {
      if (!s[i].is_string() || s[i].get<std::string>().find('=') == std::string::npos)
        fail("scene: '", json::child(json::child(path, "set"), i),
             "' must be a string KEY=VALUE (as nsf calibrate --set), got ", s[i].dump());
      c.set.push_back(s[i].get<std::string>());
    }
  }
  return c;
}

}  // namespace

TrainSection parse_train_section(const nlohmann::json& train, const std::string& path) {
  json::require_object(train, path);
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
  if (train.contains("calibrate")) {
    const nlohmann::json& c = train.at("calibrate");
    const std::string where = json::child(path, "calibrate");
    if (!c.is_array()) {
      t.calibrate.push_back(parse_calibration_recipe(c, where));
    } else {
      if (c.empty())
        fail("scene: '", where, "' must be a recipe object or a non-empty list of them");
      for (size_t i = 0; i < c.size(); ++i)
        t.calibrate.push_back(parse_calibration_recipe(c[i], json::child(where, i)));
    }
  }
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
