#include "rom/setup/rom_setup.h"

#include <sstream>

#include "core/error.h"
#include "data/sweep_spec.h"
#include "rom/setup/rom_section.h"

namespace nsf {

namespace {

// The scene's JSON at μ, through its sweep's templates.
void apply_mu(const NeuralFields& fields, const std::string& model, const SceneFile& file,
              std::optional<double> mu, RomSetup& s) {
  s.json = file.json;
  if (file.sections.sweep) {
    const SweepSpec& spec = *file.sections.sweep;
    if (!mu)
      fail("scene ", file.path, " varies '", spec.parameter, "' over [", spec.lo, ", ", spec.hi,
           "]; give its value (nsf rom --mu, RuntimeOptions::mu, Python's Rom(mu=...))");
    apply_overrides(s.json, sweep_overrides(spec, *mu));
    s.mu = *mu;
    s.has_mu = true;
    s.sweep_parameter = spec.parameter;
    if (*mu < fields.mu_min() || *mu > fields.mu_max()) {
      std::ostringstream w;
      w << "mu = " << *mu << " lies outside the training range [" << fields.mu_min() << ", "
        << fields.mu_max() << "] of " << model << ": this is extrapolation, expect larger errors";
      s.warnings.push_back(w.str());
    }
  } else if (mu) {
    fail("mu given, but scene ", file.path, " has no \"sweep\" section saying what mu is");
  } else if (fields.stress_uses_mu()) {
    fail("the model's stress field takes mu, but scene ", file.path,
         " has no \"sweep\" section to set it");
  }
}

// Whether the run reads the scene's "unseen" profile, and the warning that says why.
bool reads_unseen_profile(const std::string& given, const SceneFile& file, RomSetup& s) {
  const std::string& scenes = file.sections.rom.profile;
  const std::string& profile = given != "auto" || scenes.empty() ? given : scenes;
  if (profile != "auto" && profile != "family" && profile != "unseen")
    fail("rom profile '", profile, "' is unknown (auto, family or unseen)");
  const bool has = bool(file.sections.rom.unseen);
  if (profile == "unseen" && !has)
    fail("scene ", file.path,
         " has no rom.unseen profile (docs/GENERALIZE.md, \"Outside the training family\")");
  const bool outside = !s.outside_family.empty();
  if (outside) {
    std::string w = "this run lies outside the model's training family (" + s.outside_family[0];
    if (s.outside_family.size() > 1)
      w += "; " + std::to_string(s.outside_family.size() - 1) + " more";
    w += "): the reduced model extrapolates";
    w += profile == "family" ? ", on the family's settings as asked"
         : has               ? ", on the scene's rom.unseen profile"
                             : " (the scene has no rom.unseen profile)";
    s.warnings.push_back(w);
  }
  return has && (profile == "unseen" || (profile == "auto" && outside));
}

// The one precedence rule of rom_setup.h.
void choose_settings(const NeuralFields& fields, const SceneFile& file,
                     const RomSettingChoices& given, RomSetup& s) {
  const RomSection& scene_rom = file.sections.rom;
  const bool unseen = reads_unseen_profile(given.profile, file, s);
  s.profile = unseen ? "unseen" : "family";
  const ModelCalibration calibrated =
      unseen ? unseen_calibration_of(fields)
             : calibration_of(fields, scene_rom, given.rom.fields.stress);
  const RomSection& section =
      unseen ? *scene_rom.unseen : scene_rom.for_run(fields.family(), given.rom.fields.stress);
  if (file.json.contains("rom"))
    for (std::string& w : overrides_hidden_by(file.json.at("rom"),
                                              unseen ? "unseen" : fields.decoder(), file.overrides))
      s.warnings.push_back(std::move(w));
  RomOptions& ro = s.options = with_rom_section(given.rom, section, calibrated);
  if (given.dt_ratio) ro.dt_ratio = *given.dt_ratio;
  if (given.latent_prior) ro.latent_prior = *given.latent_prior;
  const RomSettingSources sources = rom_setting_sources(
      section, calibrated, given.latent_prior.has_value(), given.dt_ratio.has_value());
  s.dt_ratio_source = sources.dt_ratio;
  s.latent_prior_source = sources.latent_prior;
  if (given.quadrature) ro.quadrature_per_cell = *given.quadrature;
  if (given.gn_iterations) ro.inversion.max_iterations = *given.gn_iterations;
  if (given.samples) ro.sampling.count = *given.samples;
  if (given.seed) ro.sampling.seed = *given.seed;
}

}  // namespace

RomSetup rom_setup(const NeuralFields& fields, const std::string& model, const SceneFile& file,
                   std::optional<double> mu, const RomSettingChoices& given) {
  RomSetup s;
  apply_mu(fields, model, file, mu, s);
  s.scene = build_scene_file(file, s.json);
  fields.check_scene(s.scene.name, s.scene.particles.X, "scene " + file.path);
  s.outside_family = fields.training_box().scene.outside(s.json);
  choose_settings(fields, file, given, s);
  return s;
}

RomSetup rom_setup(const NeuralFields& fields, const std::string& scene_path,
                   std::optional<double> mu, const std::vector<std::string>& overrides,
                   int samples) {
  RomSettingChoices given;
  if (samples > 0) given.samples = samples;
  return rom_setup(fields, "the model", read_scene_file(scene_path, overrides), mu, given);
}

}  // namespace nsf
