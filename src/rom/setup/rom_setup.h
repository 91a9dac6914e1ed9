#pragma once
// A reduced-order run's set-up, one rule for `nsf rom`, `nsf serve`, the embedding API and
// Python: the scene file at μ (its sweep's templates applied), built and checked against the
// model, and the ROM's settings. Each setting comes from the first that gives it:
//   the caller (command line, host options) > the scene's "rom" section (the profile of the
//   model's family, or of the tracked state, first) > the model's calibration (nsf calibrate) >
//   the default.
// A run outside the model's training family (a scene value its training runs never took) reads
// the scene's "unseen" profile instead, and none of the training runs' calibration, which holds a
// run to them: only the unseen calibration, measured on perturbed cases (nsf calibrate --unseen).
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "mpm/scene/scene.h"
#include "nn/neural_fields.h"
#include "rom/rom_options.h"
#include "rom/setup/scene_file.h"

namespace nsf {

// What the caller gives; each unset value comes from the scene, then the model, then the default.
struct RomSettingChoices {
  RomOptions rom;  // its `fields` name the sources chosen; an empty one takes the scene's
  std::optional<double> dt_ratio;      // ROM step over Δt
  std::optional<double> latent_prior;  // ε (m)
  std::optional<int> quadrature;       // points per cell
  std::optional<int> gn_iterations;    // Gauss–Newton cap
  std::optional<int> samples;          // |S| at t = 0
  std::optional<uint64_t> seed;        // of the sample choice
  // Which settings of the scene's rom section: "auto" (the scene's rom.profile where it names
  // one, else the "unseen" profile for a run outside the training family and the family's for
  // one inside), "family" or "unseen".
  std::string profile = "auto";
};

struct RomSetup {
  Scene scene;
  nlohmann::json json;  // the scene at μ, as built
  double mu = 0;        // 0 for a scene without a sweep
  bool has_mu = false;
  std::string sweep_parameter;  // what μ is (the scene's sweep.parameter)
  RomOptions options;
  // Where ε and the step came from: "command line", "scene", "model" or "default".
  std::string latent_prior_source, dt_ratio_source;
  // What of the scene lies outside the model's training family (data/scene_family.h), one line
  // per value; empty inside it, or for a model that never recorded its family.
  std::vector<std::string> outside_family;
  // The settings read: "family" or "unseen" (the scene's rom.unseen profile).
  std::string profile = "family";
  // μ outside the model's training range; `--set rom.KEY` overrides a family profile hides.
  std::vector<std::string> warnings;
};

// Throws nsf::Error naming the file and the problem. `model` names the model in warnings.
RomSetup rom_setup(const NeuralFields& fields, const std::string& model, const SceneFile& file,
                   std::optional<double> mu, const RomSettingChoices& given = {});

// The same from a scene path and its overrides, as a host gives them; `samples` > 0 sets |S|.
RomSetup rom_setup(const NeuralFields& fields, const std::string& scene_path,
                   std::optional<double> mu, const std::vector<std::string>& overrides,
                   int samples);

}  // namespace nsf
