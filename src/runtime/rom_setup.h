#pragma once
// A reduced-order run as the embedding API sets it up: the scene file at μ (its sweep
// templates applied), built, and the ROM settings its "rom" section gives.
#include <optional>
#include <string>
#include <vector>

#include "mpm/scene/scene.h"
#include "nn/neural_fields.h"
#include "rom/rom_options.h"

namespace nsf {

struct RomSetup {
  Scene scene;
  double mu = 0;  // 0 for a scene without a sweep
  RomOptions options;
};

// Reads the scene file with `overrides`, parses its "sweep" and "rom" sections, applies μ and
// builds the scene; checks it is the model's. `samples` > 0 overrides the scene's |S|. Throws
// nsf::Error naming the file and the problem.
RomSetup rom_setup(const NeuralFields& fields, const std::string& scene_path,
                   std::optional<double> mu, const std::vector<std::string>& overrides,
                   int samples);

}  // namespace nsf
