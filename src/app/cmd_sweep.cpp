// `nsf sweep scene.json --out data/NAME`: the training and test simulations of a scene's sweep;
// under `mpirun -np K`, shared by K processes (app/sweep_ranks.h).
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/common_options.h"
#include "app/sweep_ranks.h"
#include "core/progress.h"
#include "data/sweep.h"
#include "rom/setup/scene_file.h"

namespace nsf::app {

namespace {

struct SweepArgs {
  std::string scene, out, only;
  std::vector<std::string> overrides;
  int jobs = 0, threads = 0, gzip = 0;
  bool quiet = false;
};

void sweep(const SweepArgs& a, SweepRanks& ranks) {
  const int cores = ranks.cores();
  SweepOptions opt;
  opt.out_dir = a.out;
  opt.overrides = a.overrides;
  opt.only = a.only;
  opt.gzip = a.gzip;
  // Default: one single-threaded simulation per core. Measured on the small paper scenes
  // (docs/DATASETS.md), independent runs beat OpenMP inside one run by far: the small grids give
  // OpenMP little work per barrier, and runs share nothing.
  opt.jobs = a.jobs > 0 ? a.jobs : cores;
  opt.threads = a.threads > 0 ? a.threads : std::max(1, cores / opt.jobs);
  // One progress line and one summary: process 0's.
  opt.quiet = a.quiet || ranks.rank() > 0;
  opt.team = ranks.team();
  if (opt.jobs * opt.threads > cores)
    std::fprintf(stderr, "nsf sweep: warning: %d jobs x %d threads > %d cores\n", opt.jobs,
                 opt.threads, cores);
  if (ranks.size() > 1 && ranks.rank() == 0)
    std::fprintf(stderr, "nsf sweep: %s -> %s, %d processes x %d jobs x %d threads\n",
                 a.scene.c_str(), a.out.c_str(), ranks.size(), opt.jobs, opt.threads);
  else if (ranks.size() == 1)
    std::fprintf(stderr, "nsf sweep: %s -> %s, %d jobs x %d threads\n", a.scene.c_str(),
                 a.out.c_str(), opt.jobs, opt.threads);
  const SceneFile scene = read_scene_file(a.scene, a.overrides);
  const SweepSummary s = run_sweep(scene.json, scene.sections.sweep, scene.path, opt);
  if (ranks.rank() > 0) return;
  std::printf("sweep: %d runs, %d simulated, %d already complete, %s; manifest %s/manifest.json\n",
              s.planned, s.ran, s.skipped, Progress::format_seconds(s.seconds).c_str(),
              a.out.c_str());
}

void run_sweep_command(const SweepArgs& a) {
  SweepRanks ranks;
  ranks.run([&] { sweep(a, ranks); });
}

}  // namespace

void add_sweep_command(CLI::App& app) {
  auto args = std::make_shared<SweepArgs>();
  CLI::App* cmd =
      app.add_subcommand("sweep", "Run a scene's training and test simulations (its \"sweep\")");
  cmd->add_option("scene", args->scene, "Scene JSON file with a sweep section")->required();
  cmd->add_option("--out,-o", args->out, "Output directory (run files and manifest.json)")
      ->required();
  cmd->add_option("--jobs", args->jobs, "Simulations run at once (0 = one per core)")
      ->capture_default_str()
      ->check(in_range(0, 256));
  // -J was --jobs' short name until -j meant threads on every command: it still works, listed
  // apart (CLI11's errors cannot name a hidden option).
  auto* old_jobs = cmd->add_option("-J", args->jobs, "Old name of --jobs (-j is --threads)")
                       ->check(in_range(0, 256))
                       ->group("Deprecated");
  add_threads_option(cmd, args->threads, "OpenMP threads per simulation", "cores / jobs");
  cmd->add_option("--only", args->only, "Only this split")->check(CLI::IsMember({"train", "test"}));
  cmd->add_option("--set", args->overrides, "Override a scene value, e.g. --set material.E=5")
      ->type_name("KEY=VALUE")
      ->check(override_syntax());
  add_gzip_option(cmd, args->gzip);
  add_quiet_flag(cmd, args->quiet);
  cmd->callback([args, old_jobs] {
    if (old_jobs->count() > 0)
      std::fprintf(stderr, "nsf sweep: note: -J is deprecated; use --jobs (-j is --threads)\n");
    run_sweep_command(*args);
  });
}

}  // namespace nsf::app
