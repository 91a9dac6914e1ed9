#pragma once
// A scene's optional "rom" section: the sample particles (rom/step/sampling.h), the ROM's own time
// step, its latent prior, its quadrature, its Gauss–Newton cap and its field sources — the
// settings measured best for the scene (docs/ROM.md). The command line overrides each of them.
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "nn/neural_fields.h"
#include "rom/rom_options.h"
#include "rom/step/sampling.h"

namespace nsf {

struct RomSection {
  SamplingSpec sampling;
  std::optional<double> dt_ratio;      // ROM step over the scene's Δt (RomOptions::dt_ratio)
  std::optional<double> latent_prior;  // ε of the latent prior, m (RomOptions::latent_prior)
  std::optional<int> quadrature;       // points per cell (RomOptions::quadrature_per_cell)
  std::optional<int> gn_iterations;    // GaussNewtonOptions::max_iterations
  std::optional<double> gn_damping;    // GaussNewtonOptions::damping
  std::optional<double> cfl;           // the tracked state's CFL factor (RomOptions::cfl)
  std::optional<double> grid;  // the ROM grid's Δx over the scene's (RomOptions::grid_factor)
  std::optional<std::vector<int>> rigid_frames;  // RomOptions::rigid_frames
  FieldChoice fields;  // "fields": {"deformation", "stress", "affine"} by name
  // "mlp", "basis": settings for a model of that decoder family, over the ones above (a scene
  // whose two families were measured best at different steps, priors or sample counts).
  std::shared_ptr<const RomSection> mlp, basis;
  // "tracked": settings for a run whose points carry their own stress (fields.stress "tracked"),
  // over the ones above: that state integrates differently (an explicit stress within the CFL
  // bound, no h to drift from), so its best step and prior are its own. Null where not given.
  std::shared_ptr<const RomSection> tracked;
  // "unseen": settings for a run outside the model's training family (a scene value its training
  // runs never took: data/scene_family.h), over the common ones above, in place of the family's
  // and tracked objects. The learned stress and a latent prior calibrated on the training runs
  // hold a run to what those runs did; such a run is better served by the material law (the
  // tracked state) and no prior. Null where not given.
  std::shared_ptr<const RomSection> unseen;
  // "profile": which of those a run reads, "auto" (unseen outside the training family), "family"
  // or "unseen"; "" where not given (auto). A host sets it through its scene overrides.
  std::string profile;

  // The section as a model of `family` (NeuralFields::family()) reads it.
  const RomSection& for_family(DecoderFamily family) const;
  // Whether a run of such a model carries the tracked state: `stress`, a command line's choice of
  // stress source, else the family's fields.stress, is "tracked".
  bool tracks_stress(DecoderFamily family, const std::string& stress = "") const;
  // What that run reads: the family's settings, with the tracked ones over them where it tracks.
  const RomSection& for_run(DecoderFamily family, const std::string& stress = "") const;
};

// Reads the whole section; missing keys keep their defaults, a null section gives all defaults.
// A family's object takes the same keys, but no family of its own.
// Throws nsf::Error naming the key for a malformed value.
RomSection parse_rom_section(const nlohmann::json& rom);

// What `nsf calibrate` chose for a model (its calibration record,
// rom/calibration/rom_calibration.h); < 0 where it chose nothing. A run that carries the tracked
// state (as rom.tracks_stress says, `stress` a command line's choice of stress source) takes the
// tracked calibration where the model has one, else the other (a model calibrated once).
struct ModelCalibration {
  double latent_prior = -1;
  double dt_ratio = -1;
};
ModelCalibration calibration_of(const NeuralFields& fields, const RomSection& rom,
                                const std::string& stress = "");
// What `nsf calibrate --unseen` chose for a run on the scene's unseen profile, measured on cases
// outside the training family; < 0 where it chose nothing (the training runs' calibration never
// reaches such a run).
ModelCalibration unseen_calibration_of(const NeuralFields& fields);

// `options` with the section's settings: its sampling, and each other value the section gives;
// a field source only where `options` names none (a command line's own choice wins). A section
// without latent_prior or dt_ratio takes the model's calibrated one where it has one.
RomOptions with_rom_section(RomOptions options, const RomSection& section,
                            const ModelCalibration& calibrated = {});

// The scene overrides (`--set rom.KEY=VALUE`) whose KEY the rom section's `profile` object (a
// decoder family's, "unseen") sets again, so that the override does not reach a run that reads
// that object: one line each, naming both.
std::vector<std::string> overrides_hidden_by(const nlohmann::json& rom, const std::string& profile,
                                             const std::vector<std::string>& overrides);

// Where ε and the step of with_rom_section's options came from, for a run whose command line
// gave (or did not give) its own: "command line", "scene", "model" (its calibration) or
// "default". A run's report and its results row record them.
struct RomSettingSources {
  std::string latent_prior, dt_ratio;
};
RomSettingSources rom_setting_sources(const RomSection& section, const ModelCalibration& calibrated,
                                      bool prior_given, bool dt_ratio_given);

}  // namespace nsf
