// `nsf rom models/NAME.nsf scene.json --mu V --samples K`: a reduced-order run at parameter μ,
// timed against the full-order engine on the same scene in the same process.
#include <cstdio>
#include <limits>

#include "app/commands.h"
#include "app/common_options.h"
#include "app/retired_options.h"
#include "core/path_clash.h"
#include "core/strings.h"
#include "data/manifest.h"
#include "io/xdmf_writer.h"
#include "rom/eval/result_row.h"
#include "rom/eval/results_page.h"
#include "rom/eval/rom_evaluation.h"
#include "rom/fields/field_source.h"

namespace nsf::app {

namespace {

struct RomArgs {
  RomEvalOptions opt;
  double mu = 0;
  int samples = 0;
  double dt_ratio = 1;
  double latent_prior = 0;
  uint64_t seed = 1;
  bool crom = false;
  bool no_full_order = false;
  std::string json;
  int gn_iterations = 3, quadrature = 0;
};

}  // namespace

void add_rom_command(CLI::App& app) {
  auto a = std::make_shared<RomArgs>();
  CLI::App* cmd = app.add_subcommand(
      "rom", "Reduced-order (latent-space) simulation of a scene with a trained model");
  cmd->add_option("model", a->opt.model_path, "Model file (nsf train)")->required();
  cmd->add_option("scene", a->opt.scene_path, "Scene JSON (the model's scene)")->required();
  auto* mu = cmd->add_option("--mu", a->mu,
                             "The scene's sweep parameter (e.g. friction angle), applied "
                             "through its \"sweep\" templates")
                 ->check(in_range(-1e300, 1e300));
  cmd->add_option("--set", a->opt.overrides, "Override a scene value, e.g. --set material.E=5")
      ->type_name("KEY=VALUE")
      ->check(override_syntax());
  auto* samples = cmd->add_option("--samples,-k", a->samples,
                                  "Sample particles |S| (default: the scene's rom.samples, or 256)")
                      ->check(in_range(1, 100000000));
  auto* seed = cmd->add_option("--seed", a->seed,
                               "Seed of the sample choice (default: the scene's rom.seed, or 1)")
                   ->check(in_range<long long>(0, std::numeric_limits<long long>::max()));
  cmd->add_option("--out,-o", a->opt.out_path,
                  "Write the ROM run here (HDF5, nsf simulate layout)");
  cmd->add_option("--truth", a->opt.truth_path,
                  "Ground-truth run file for delta (default: the full-order run made here)");
  cmd->add_option("--fom-out", a->opt.fom_out, "Keep the full-order run in this file");
  cmd->add_flag("--no-full-order", a->no_full_order,
                "Skip the full-order run (no speed-up; delta only with --truth)");
  cmd->add_option("--upsample", a->opt.upsample,
                  "Write k points per particle, queried from g (Fig. 6)")
      ->capture_default_str()
      ->check(in_range(1, 64));
  auto* dt_ratio = add_dt_ratio_option(
      cmd, a->dt_ratio,
      "default: the scene's rom.dt_ratio, or 1; at most the scene's substeps per frame");
  auto* latent_prior =
      cmd->add_option("--latent-prior", a->latent_prior,
                      "Hold the inversion near the training runs' latents: a latent one training "
                      "spread off them costs as much as every sample this far out of place, in "
                      "metres (default: the scene's rom.latent_prior, else the model's calibration "
                      "(nsf calibrate), else 0 = none, the paper)")
          ->check(in_range(0.0, 1e3));
  auto* gn_iterations =
      cmd->add_option("--gn-iterations", a->gn_iterations,
                      "Gauss-Newton iteration cap (default: the scene's rom.gn_iterations, or 3)")
          ->check(in_range(1, 1000));
  cmd->add_option("--gn-tolerance", a->opt.rom.inversion.tolerance,
                  "Stop when |dz| <= tol (1 + |z|)")
      ->capture_default_str()
      ->check(in_range(0.0, 1.0));
  add_profile_option(cmd, a->opt.profile);
  add_guard_flag(cmd, a->opt.guard);
  cmd->add_flag("--taylor", a->opt.rom.inversion.taylor,
                "First-order Taylor inversion: one linearised step per time step");
  // Field sources by name (rom/fields/field_registry.cpp); each option lists the registered ones.
  cmd->add_option("--deformation", a->opt.rom.fields.deformation,
                  "Positions on the candidates from: " + join(deformation_source_names()) +
                      " (default: the scene's rom.fields, else the model's decoder g)")
      ->check(not_a_retired_source("deformation"))
      ->check(CLI::IsMember(deformation_source_names()));
  cmd->add_option(
         "--stress", a->opt.rom.fields.stress,
         "Kirchhoff stress on N from: " + join(point_field_source_names(FieldRole::stress)) +
             " (default: the scene's rom.fields, else the model's decoder h; crom: from dg/dX "
             "through the material; tracked: each integration point's own F and plastic state, "
             "carried through the run, as full order carries each particle's)")
      ->check(not_a_retired_source("stress"))
      ->check(CLI::IsMember(point_field_source_names(FieldRole::stress)));
  cmd->add_option(
         "--affine", a->opt.rom.fields.affine,
         "APIC affine matrices C on N from: " + join(point_field_source_names(FieldRole::affine)) +
             " (default: the scene's rom.fields, else the model's decoder l, or none with --stress "
             "crom; tracked: each integration point's own G2P C)")
      ->check(not_a_retired_source("affine"))
      ->check(CLI::IsMember(point_field_source_names(FieldRole::affine)));
  cmd->add_option("--velocity", a->opt.rom.fields.velocity,
                  "Velocities on N from: " + join(velocity_source_names()) +
                      " (default: the scene's rom.fields, else latent: g's backward difference, "
                      "the paper; tracked: each integration point's own G2P velocity of the step "
                      "before, as full order carries each particle's)")
      ->check(CLI::IsMember(velocity_source_names()));
  cmd->add_flag("--crom", a->crom,
                "CROM-style baseline: --stress crom (and --affine none unless given)");
  cmd->add_option("--halo", a->opt.rom.halo, "Candidate margin around the grid nodes I, in cells")
      ->capture_default_str()
      ->check(in_range(1.01, 64.0));
  auto* quadrature =
      cmd->add_option("--quadrature", a->quadrature,
                      "Integrate the MPM step on N with this many points per grid cell of the "
                      "rest shape, each merging a group of particles (their mass, volume, centre "
                      "of mass); the sample particles stay themselves (0 = every particle, the "
                      "paper; default: the scene's rom.quadrature, or 0)")
          ->check(in_range(0, 1000));
  add_threads_option(cmd, a->opt.threads, "Threads, the same for both engines");
  add_gzip_option(cmd, a->opt.gzip);
  add_quiet_flag(cmd, a->opt.quiet);
  cmd->add_flag("--budget", a->opt.budget,
                "Also measure the error budget on the truth's frames: the truth encoded, and the "
                "truth's sample positions fitted by the inversion (docs/ROM.md)");
  cmd->add_option("--baselines", a->opt.baseline_data,
                  "Also score look-up (the nearest training run in mu, played back) and "
                  "interpolation in mu of this dataset's training runs against the same truth")
      ->type_name("DATA");
  cmd->add_option(
         "--coarse", a->opt.coarse_scene,
         "Also score the full-order engine on this coarser scene (with --set) at the same mu, its "
         "particles carried to the truth's (delta and its speed-up; docs/RESULTS.md)")
      ->type_name("SCENE");
  cmd->add_option("--coarse-factor", a->opt.coarse_factor,
                  "Make the coarse scene (--coarse, else this scene) k times coarser in dx (and "
                  "dt where the substeps divide by k)")
      ->check(in_range(1.01, 64.0));
  cmd->add_option("--json", a->json,
                  "Also write the summary as one JSON row, the format of docs/results/*.json "
                  "(delta, speed-up, times, memory)");
  add_retired_options(cmd, "rom");
  cmd->callback([a, mu, samples, dt_ratio, latent_prior, seed, gn_iterations, quadrature] {
    if (*gn_iterations) a->opt.gn_iterations = a->gn_iterations;
    if (*quadrature) a->opt.quadrature = a->quadrature;
    if (*mu) a->opt.mu = a->mu;
    if (*seed) a->opt.seed = a->seed;
    if (a->crom) a->opt.rom.fields.stress = "crom";
    if (*samples) a->opt.samples = a->samples;
    if (*dt_ratio) a->opt.dt_ratio = a->dt_ratio;
    if (*latent_prior) a->opt.latent_prior = a->latent_prior;
    a->opt.full_order = !a->no_full_order;
    const RomEvalOptions& o = a->opt;
    refuse_path_clash({{"--out", o.out_path},
                       {"the XDMF sidecar of --out",
                        o.out_path.empty() ? std::string() : xdmf_path_for(o.out_path)},
                       {"--fom-out", o.fom_out},
                       {"the XDMF sidecar of --fom-out",
                        o.fom_out.empty() ? std::string() : xdmf_path_for(o.fom_out)},
                       {"--json", a->json}},
                      {{"the model", o.model_path},
                       {"the scene", o.scene_path},
                       {"--truth", o.truth_path},
                       {"--coarse", o.coarse_scene}});
    set_threads(a->opt.threads);
    const RomReport r = evaluate_rom(a->opt);
    std::printf("%s", format_rom_report(r).c_str());
    if (!a->json.empty())
      write_json_atomically(a->json, result_json(r, a->opt.scene_path, a->opt.model_path, "", ""));
  });
}

}  // namespace nsf::app
