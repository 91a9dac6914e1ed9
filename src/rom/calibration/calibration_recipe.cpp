#include "rom/calibration/calibration_recipe.h"

#include <cmath>

#include "core/error.h"
#include "core/json_util.h"

namespace nsf {

namespace {

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
  json::check_keys(j, path, {"grid", "dt_ratios", "set", "unseen", "draws"});
  CalibrationRecipe c;
  if (j.contains("unseen")) {
    if (!j.at("unseen").is_boolean())
      fail("scene: '", json::child(path, "unseen"),
           "' must be true or false (calibrate the rom.unseen profile on perturbed cases), got ",
           j.at("unseen").dump());
    c.unseen = j.at("unseen").get<bool>();
  }
  if (j.contains("draws")) {
    if (!c.unseen)
      fail("scene: '", json::child(path, "draws"),
           "' counts perturbed cases: it goes with \"unseen\": true");
    c.draws = json::get_int(j, path, "draws", 1, 1000);
  }
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

std::vector<CalibrationRecipe> parse_calibration_recipes(const nlohmann::json& train,
                                                         const std::string& path) {
  std::vector<CalibrationRecipe> recipes;
  if (!train.is_object() || !train.contains("calibrate")) return recipes;
  const nlohmann::json& c = train.at("calibrate");
  const std::string where = json::child(path, "calibrate");
  if (!c.is_array()) {
    recipes.push_back(parse_calibration_recipe(c, where));
  } else {
    if (c.empty()) fail("scene: '", where, "' must be a recipe object or a non-empty list of them");
    for (size_t i = 0; i < c.size(); ++i)
      recipes.push_back(parse_calibration_recipe(c[i], json::child(where, i)));
  }
  return recipes;
}

}  // namespace nsf
