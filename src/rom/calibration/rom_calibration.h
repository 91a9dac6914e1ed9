#pragma once
// The ROM's calibration of a model, its own record (docs/ROM.md, "Latent prior"): what
// `nsf calibrate` chose for each kind of ROM run, stored in the model file as the attachment
// "rom_calibration", which nn keeps without reading (NeuralFields::attachment). The ROM's setup
// (rom/setup/rom_section.h) reads it; store_calibration
// (rom/calibration/latent_prior_calibration.h) writes it. The record is one JSON object whose
// entries are named as model files of format versions 1-8 named them in the archive itself, so that
// nn hands an old file's entries over unchanged (docs/TRAINING.md, "Model file"):
//   latent_prior, latent_prior_calibration, calibrated_dt_ratio   the run whose stress the
//       decoders give: ε (metres), its table (JSON), the step over the scene's Δt
//   tracked_latent_prior, tracked_latent_prior_calibration, tracked_calibrated_dt_ratio   the
//       same for the run whose points carry their own stress (the tracked state)
//   unseen_latent_prior, unseen_latent_prior_calibration, unseen_calibrated_dt_ratio   the same
//       for a run on the scene's rom.unseen profile, measured on perturbed runs
//       (`nsf calibrate --unseen`); its table names the seed of the draws it measured
// each absent where never chosen.
#include <nlohmann/json.hpp>
#include <string>

namespace nsf {

class NeuralFields;

// What `nsf calibrate` chose for one kind of ROM run.
struct RomCalibration {
  double latent_prior = -1;  // ε (metres; 0: none chosen); < 0 where never calibrated
  double dt_ratio = -1;  // the step over the scene's Δt (--dt-ratios); ≤ 0 where never chosen
  nlohmann::json table;  // the ε and steps tried, the training runs, δ of each; null: none
};

// The calibrations of a model: for the ROM whose stress the decoders give (h, or what stands in
// for it), and for the ROM whose points carry their own (the tracked state). The two integrate
// differently, so each has its own. And for a run outside the training family, on the scene's
// unseen profile, measured on cases outside the family too.
struct RomCalibrations {
  RomCalibration decoded, tracked, unseen;
};

// The name of the model file's attachment that holds it.
constexpr const char* kRomCalibrationAttachment = "rom_calibration";

nlohmann::json to_json(const RomCalibrations& c);
// Throws nsf::Error naming `what` (the model file) and the entry for a malformed record.
RomCalibrations rom_calibrations_from_json(const nlohmann::json& j, const std::string& what);

// The model's calibrations (never calibrated: both at their defaults).
RomCalibrations rom_calibrations(const NeuralFields& fields);

}  // namespace nsf
