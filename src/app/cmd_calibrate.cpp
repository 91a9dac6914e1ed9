// `nsf calibrate models/NAME.nsf data/NAME [--dt-ratios 1,1.5,2] [--unseen]`: choose the model's
// latent prior ε (and the ROM's step) on its training runs, or its unseen profile's on perturbed
// cases, and store them in the model file (rom/calibration/latent_prior_calibration.h,
// docs/ROM.md).
#include <cstdio>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/common_options.h"
#include "core/error.h"
#include "io/atomic_file.h"
#include "nn/neural_fields.h"
#include "rom/calibration/latent_prior_calibration.h"

namespace nsf::app {

namespace {

struct CalibrateArgs {
  CalibrationOptions opt;
  std::string json;
  bool dry_run = false;
  int recipe = 1;  // of the scene's train.calibrate list, from 1
  int seed = -1;   // --seed; < 0: not given
};

// A scene whose rom section sets latent_prior (or dt_ratio, where the step was calibrated) for
// the model's decoder family, and the kind of run calibrated, overrides the model's calibration
// in `nsf rom`.
void warn_if_scene_overrides(const CalibrationOptions& o, DecoderFamily decoders, bool step) {
  const SceneRomSettings scene = scene_rom_settings(o, decoders);
  const std::string family = family_name(decoders);
  const std::string where = o.unseen        ? "unseen object"
                            : scene.tracked ? "tracked object"
                                            : family + " object";
  const auto warn = [&](const char* key, const std::string& value, const char* unit) {
    std::fprintf(stderr,
                 "nsf: warning: the scene sets rom.%s = %s%s for %s%s, which nsf rom uses "
                 "ahead of the model's calibration; remove it there (or set it to null in its "
                 "rom.%s) to use the calibration\n",
                 key, value.c_str(), unit,
                 o.unseen ? "runs on its unseen profile" : (family + " models").c_str(),
                 scene.tracked && !o.unseen ? " with the tracked state" : "", where.c_str());
  };
  if (scene.latent_prior) {
    std::ostringstream prior;
    prior << *scene.latent_prior;
    warn("latent_prior", prior.str(), " m");
  }
  if (scene.dt_ratio && step) warn("dt_ratio", dt_ratio_arg(*scene.dt_ratio), "");
}

}  // namespace

void add_calibrate_command(CLI::App& app) {
  auto a = std::make_shared<CalibrateArgs>();
  CLI::App* cmd = app.add_subcommand(
      "calibrate",
      "Choose a model's latent prior on its training runs (the ROM at each length of a grid, "
      "the lowest mean delta wins), optionally its ROM step, and store them in the model file");
  cmd->add_option("model", a->opt.model_path, "Model file (nsf train); rewritten in place")
      ->required();
  cmd->add_option("data", a->opt.data_dir, "The dataset it was trained on")->required();
  cmd->add_option("--scene", a->opt.scene_path,
                  "Scene file whose rom section the ROM runs with (default: the dataset "
                  "manifest's scene_file)");
  CLI::Option* set =
      cmd->add_option("--set", a->opt.overrides,
                      "Override a scene value for the ROM runs, e.g. --set rom.quadrature=1 (the "
                      "setting the model will run with; default: the scene's train.calibrate.set)")
          ->type_name("KEY=VALUE")
          ->check(override_syntax());
  CLI::Option* grid =
      add_list_option(cmd, "--grid", a->opt.grid,
                      "Latent prior lengths to try, metres, comma-separated (0: none; default: the "
                      "scene's train.calibrate.grid, else 0,0.0001,0.0003,0.001,0.002)",
                      0.0, 1e3);
  CLI::Option* dt_ratios = add_list_option(
      cmd, "--dt-ratios", a->opt.dt_ratios,
      "Also choose the ROM's step: ratios to the scene's dt to try, ascending "
      "(e.g. 1,1.5,2,3,4; default: the scene's train.calibrate.dt_ratios); at the chosen prior, "
      "the largest whose mean delta is within "
      "--dt-tolerance of the best's (or within --dt-budget) wins, and nsf rom takes "
      "it where the scene's rom "
      "section sets no dt_ratio",
      1e-3, 1e3);
  cmd->add_option("--dt-tolerance", a->opt.dt_tolerance,
                  "How much larger than the best ratio's mean delta a ratio's may be")
      ->capture_default_str()
      ->check(in_range(1.0, 100.0));
  cmd->add_option("--dt-budget", a->opt.dt_budget,
                  "Or at most this mean delta (e.g. 0.01 for 1 %; 0: only --dt-tolerance)")
      ->check(in_range(0.0, 1.0));
  cmd->add_option("--runs", a->opt.runs, "Training runs to measure on, spread over the sweep")
      ->capture_default_str()
      ->check(in_range(1, 1000));
  CLI::Option* unseen = cmd->add_flag(
      "--unseen", a->opt.unseen,
      "Calibrate the scene's rom.unseen profile instead, on perturbed cases drawn from its "
      "generalize section (never the benchmark's draws), each run at full order once; a run "
      "outside the training family takes it (default: the scene's train.calibrate.unseen)");
  CLI::Option* draws =
      cmd->add_option("--draws", a->opt.draws,
                      "Perturbed cases to measure on, with --unseen (default: the scene's "
                      "train.calibrate.draws, else 4)")
          ->check(in_range(1, 1000));
  cmd->add_option("--seed", a->seed,
                  "Seed of those draws (default: the scene's generalize.calibration_seed); never "
                  "the benchmark's")
      ->check(in_range(0, 1 << 30));
  cmd->add_option("--recipe", a->recipe,
                  "Which of the scene's train.calibrate recipes fills what the command line does "
                  "not give, where it has several (one per kind of run: the decoded stress's, the "
                  "tracked state's)")
      ->capture_default_str()
      ->check(in_range(1, 100));
  cmd->add_option("--json", a->json, "Also write the table as JSON");
  cmd->add_flag("--dry-run", a->dry_run, "Measure and print, leave the model file as it is");
  add_threads_option(cmd, a->opt.threads);
  add_quiet_flag(cmd, a->opt.quiet);
  cmd->callback([a, grid, dt_ratios, set, unseen, draws] {
    // Checked here, before anything is read, as a usage error: the list's values are in range.
    for (size_t i = 1; i < a->opt.dt_ratios.size() && dt_ratios->count() > 0; ++i)
      if (!(a->opt.dt_ratios[i] > a->opt.dt_ratios[i - 1])) {
        std::ostringstream why;
        why << "must be ascending (the first is the reference), got " << a->opt.dt_ratios[i]
            << " after " << a->opt.dt_ratios[i - 1];
        throw CLI::ValidationError("--dt-ratios", why.str());
      }
    // The scene's train.calibrate recipe where the command line gives none of its own.
    apply_calibration_recipe(a->opt,
                             {grid->count() > 0, dt_ratios->count() > 0, set->count() > 0,
                              unseen->count() > 0, draws->count() > 0},
                             size_t(a->recipe - 1));
    if (a->seed >= 0) {
      if (!a->opt.unseen)
        throw CLI::ValidationError("--seed", "seeds the perturbed cases of --unseen");
      a->opt.seed = uint64_t(a->seed);
    }
    const CalibrationResult r = calibrate_latent_prior(a->opt);
    std::printf("%s%s", r.table().c_str(), r.summary().c_str());
    warn_if_scene_overrides(a->opt, NeuralFields::load(a->opt.model_path).family(),
                            !a->opt.dt_ratios.empty());
    if (!a->json.empty()) write_file_atomic(a->json, r.to_json().dump(2) + "\n");
    if (a->dry_run) return;
    store_calibration(a->opt.model_path, r);
    std::printf("  stored in %s\n", a->opt.model_path.c_str());
  });
}

}  // namespace nsf::app
