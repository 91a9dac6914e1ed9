#include "runtime/rom_setup.h"

#include <filesystem>

#include "core/error.h"
#include "data/sweep_spec.h"
#include "rom/rom_section.h"

namespace nsf {

RomSetup rom_setup(const NeuralFields& fields, const std::string& scene_path,
                   std::optional<double> mu, const std::vector<std::string>& overrides,
                   int samples) {
  nlohmann::json js = read_scene_json(scene_path, overrides);
  RomSetup s;
  RomSection section;
  try {
    if (js.contains("rom")) section = parse_rom_section(js.at("rom"));
    if (js.contains("sweep")) {
      const SweepSpec spec = parse_sweep(js.at("sweep"), js);
      if (!mu)
        fail("the scene varies '", spec.parameter, "' over [", spec.lo, ", ", spec.hi,
             "]; give its value as RuntimeOptions::mu");
      apply_overrides(js, sweep_overrides(spec, *mu));
      s.mu = *mu;
    } else if (mu) {
      fail("mu given, but the scene has no \"sweep\" section saying what mu is");
    } else if (fields.stress_uses_mu()) {
      fail("the model's stress field takes mu, but the scene has no \"sweep\" section to set it");
    }
    s.scene = build_scene(js, std::filesystem::path(scene_path).parent_path().string());
  } catch (const Error& e) {
    fail(scene_path, ": ", e.what());
  }
  fields.check_scene(s.scene.name, s.scene.particles.X, "scene " + scene_path);

  s.options = with_rom_section(RomOptions(), section.for_run(fields.decoder()),
                               calibration_of(fields, section));
  if (samples > 0) s.options.sampling.count = samples;
  return s;
}

}  // namespace nsf
