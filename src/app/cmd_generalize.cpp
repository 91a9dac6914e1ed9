// `nsf generalize MODEL DATA --scene SCENE`: the benchmark of unseen interactions (issue #55,
// docs/GENERALIZE.md). Draws cases from the scene's "generalize" section, scores the ROM on each
// against a fresh full-order run with the simple baselines beside it, and writes one JSON file
// per scene (docs/results/generalize/SCENE.json with --docs).
#include <cstdio>
#include <filesystem>
#include <limits>
#include <sstream>

#include "app/commands.h"
#include "app/common_options.h"
#include "core/error.h"
#include "io/atomic_file.h"
#include "rom/calibration/latent_prior_calibration.h"
#include "rom/eval/generalize.h"
#include "rom/eval/result_row.h"
#include "rom/eval/results_page.h"
#include "rom/eval/rom_evaluation.h"

namespace nsf::app {

namespace {

struct GeneralizeArgs {
  GeneralizeOptions opt;
  long long seed = 1;
  double latent_prior = 0, dt_ratio = 1;
  int samples = 0;
  bool tracked = false;
  std::string json, docs;
};

std::string quoted_arg(const std::string& s) {
  return s.find_first_of(" \t'\"$") == std::string::npos ? s : "'" + s + "'";
}

// The command line that makes the rows again, for the JSON and the page.
std::string command_of(const GeneralizeArgs& a, const CLI::App& cmd) {
  std::ostringstream c;
  c << "nsf generalize " << quoted_arg(a.opt.model_path) << " " << quoted_arg(a.opt.data_dir)
    << " --scene " << quoted_arg(a.opt.scene_path);
  for (const std::string& s : a.opt.overrides) c << " --set " << quoted_arg(s);
  if (cmd.count("--draws")) c << " --draws " << a.opt.draws;
  if (cmd.count("--seed")) c << " --seed " << a.seed;
  for (int k : a.opt.only) c << " --draw " << k;
  if (a.tracked) c << " --tracked";
  if (cmd.count("--samples")) c << " --samples " << a.samples;
  if (cmd.count("--latent-prior")) c << " --latent-prior " << a.latent_prior;
  if (cmd.count("--dt-ratio")) c << " --dt-ratio " << dt_ratio_arg(a.dt_ratio);
  if (cmd.count("--profile")) c << " --profile " << a.opt.rom.profile;
  if (!a.opt.coarse_scene.empty()) c << " --coarse-scene " << quoted_arg(a.opt.coarse_scene);
  if (cmd.count("--threads")) c << " -j " << a.opt.rom.threads;  // the speed-ups depend on it
  return c.str();
}

void run(GeneralizeArgs& a, const CLI::App& cmd) {
  GeneralizeOptions& o = a.opt;
  if (o.scene_path.empty()) o.scene_path = dataset_scene_file(o.data_dir);
  if (o.scene_path.empty())
    fail("generalize: the dataset ", o.data_dir,
         " names no scene file that exists here (its manifest's scene_file); give --scene");
  if (cmd.count("--seed")) o.seed = uint64_t(a.seed);
  if (cmd.count("--samples")) o.rom.samples = a.samples;
  if (cmd.count("--latent-prior")) o.rom.latent_prior = a.latent_prior;
  if (cmd.count("--dt-ratio")) o.rom.dt_ratio = a.dt_ratio;
  if (a.tracked) o.rom.rom.fields.stress = o.rom.rom.fields.affine = "tracked";
  o.rom.threads = set_threads(o.rom.threads);
  const GeneralizeResult r = run_generalize(o);
  const nlohmann::json j = generalize_json(r, command_of(a, cmd));
  std::printf("%s", format_generalize(j).c_str());
  const std::string text = j.dump(2) + "\n";
  if (!a.json.empty()) {
    write_file_atomic(a.json, text);
    std::printf("wrote %s\n", a.json.c_str());
  }
  if (!a.docs.empty()) {
    const std::filesystem::path dir = std::filesystem::path(a.docs) / "results" / "generalize";
    std::filesystem::create_directories(dir);
    const std::string row = (dir / (r.scene + ".json")).string();
    write_file_atomic(row, text);
    write_results_page(a.docs);
    std::printf("wrote %s and %s/RESULTS.md\n", row.c_str(), a.docs.c_str());
  }
}

}  // namespace

void add_generalize_command(CLI::App& app) {
  auto a = std::make_shared<GeneralizeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "generalize",
      "The benchmark of unseen interactions: the ROM on random perturbations outside the "
      "scene's sweep (its \"generalize\" section), each against a fresh full-order run, with "
      "look-up, interpolation and the coarse engine beside it");
  cmd->add_option("model", a->opt.model_path, "Model file (nsf train)")->required();
  cmd->add_option("data", a->opt.data_dir,
                  "The dataset it was trained on (look-up and interpolation play its runs back)")
      ->required();
  cmd->add_option("--scene", a->opt.scene_path,
                  "Scene file with the \"generalize\" section (default: the dataset manifest's "
                  "scene_file)");
  cmd->add_option("--set", a->opt.overrides,
                  "Override a scene value for every draw, e.g. --set rom.latent_prior=0")
      ->type_name("KEY=VALUE")
      ->check(override_syntax());
  cmd->add_option("--draws", a->opt.draws, "How many draws (default: the scene's generalize.draws)")
      ->check(in_range(1, 10000));
  cmd->add_option("--seed", a->seed, "Seed of the draws (default: the scene's generalize.seed)")
      ->check(in_range<long long>(0, std::numeric_limits<int>::max()));
  cmd->add_option("--draw", a->opt.only, "Run only this draw (by index; repeatable)")
      ->check(in_range(0, 9999));
  cmd->add_flag("--tracked", a->tracked,
                "Stress and affine from the material law on the integration points (the tracked "
                "state) instead of the learned fields");
  cmd->add_option("--samples,-k", a->samples, "Sample particles |S| (default: the scene's)")
      ->check(in_range(1, 100000000));
  cmd->add_option("--latent-prior", a->latent_prior,
                  "The inversion's latent prior, metres (default: the scene's, else the model's "
                  "calibration; 0 = none)")
      ->check(in_range(0.0, 1e3));
  add_dt_ratio_option(cmd, a->dt_ratio, "default: the scene's");
  add_profile_option(cmd, a->opt.rom.profile);
  add_guard_flag(cmd, a->opt.rom.guard);
  cmd->add_option("--coarse-scene", a->opt.coarse_scene,
                  "The coarse engine's scene (default: this scene at 1.5x dx)");
  cmd->add_option("--json", a->json, "Write the draws and the summary here (JSON)");
  cmd->add_option("--docs", a->docs,
                  "Store the JSON as DOCS/results/generalize/SCENE.json and rebuild "
                  "DOCS/RESULTS.md");
  add_threads_option(cmd, a->opt.rom.threads, "OpenMP and network threads, both engines alike");
  add_quiet_flag(cmd, a->opt.quiet);
  cmd->callback([a, cmd] { run(*a, *cmd); });
}

}  // namespace nsf::app
