#include "rom/calibration/rom_calibration.h"

#include <cmath>

#include "core/error.h"
#include "nn/neural_fields.h"

namespace nsf {

namespace {

// Written as the archive entries of format versions 1-8 were: ε and its table where ε was
// chosen, the step where one was.
void put(nlohmann::json& j, const std::string& prefix, const RomCalibration& c) {
  if (c.latent_prior >= 0) {
    j[prefix + "latent_prior"] = c.latent_prior;
    j[prefix + "latent_prior_calibration"] = c.table;
  }
  if (c.dt_ratio > 0) j[prefix + "calibrated_dt_ratio"] = c.dt_ratio;
}

RomCalibration get(const nlohmann::json& j, const std::string& prefix, const std::string& what) {
  const auto number = [&](const std::string& key, bool zero_ok) {
    const nlohmann::json& v = j.at(key);
    if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < 0 ||
        (!zero_ok && v.get<double>() == 0))
      fail(what, ": damaged ROM calibration (entry '", key, "')");
    return v.get<double>();
  };
  RomCalibration c;
  if (j.contains(prefix + "latent_prior")) {
    c.latent_prior = number(prefix + "latent_prior", true);
    // Absent from the run-time record of a file of format version 8 (the archive's has it).
    c.table = j.value(prefix + "latent_prior_calibration", nlohmann::json());
  }
  if (j.contains(prefix + "calibrated_dt_ratio"))
    c.dt_ratio = number(prefix + "calibrated_dt_ratio", false);
  return c;
}

}  // namespace

nlohmann::json to_json(const RomCalibrations& c) {
  nlohmann::json j = nlohmann::json::object();
  put(j, "", c.decoded);
  put(j, "tracked_", c.tracked);
  put(j, "unseen_", c.unseen);
  return j;
}

RomCalibrations rom_calibrations_from_json(const nlohmann::json& j, const std::string& what) {
  if (!j.is_object()) fail(what, ": damaged ROM calibration (not a JSON object)");
  return {get(j, "", what), get(j, "tracked_", what), get(j, "unseen_", what)};
}

RomCalibrations rom_calibrations(const NeuralFields& fields) {
  const std::string* text = fields.attachment(kRomCalibrationAttachment);
  if (!text) return {};
  const std::string what = "model of scene " + fields.scene_name();
  const nlohmann::json j = nlohmann::json::parse(*text, nullptr, false);
  if (j.is_discarded()) fail(what, ": damaged ROM calibration (not JSON)");
  return rom_calibrations_from_json(j, what);
}

}  // namespace nsf
