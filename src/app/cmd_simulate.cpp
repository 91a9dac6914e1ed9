// `nsf simulate scene.json --out run.h5`: run the full-order engine and save every frame.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "app/commands.h"
#include "core/error.h"
#include "core/memory.h"
#include "core/progress.h"
#include "data/run_to_file.h"
#include "io/png_render.h"
#include "mpm/simulation.h"

namespace nsf::app {

namespace {

struct SimulateArgs {
  std::string scene, out, png;
  std::vector<std::string> overrides;
  int threads = 0;
  bool quiet = false;
};

void print_breakdown(const Simulation& sim, double wall, size_t particles) {
  const StepTimes& t = sim.times();
  const double total = t.sort.seconds() + t.p2g.seconds() + t.grid_update.seconds() +
                       t.g2p.seconds() + t.stress.seconds();
  auto row = [&](const char* name, const PhaseTimer& p) {
    std::printf("  %-22s %8.3f s  %5.1f%%\n", name, p.seconds(), 100.0 * p.seconds() / total);
  };
  std::printf("time breakdown (%ld steps):\n", sim.step_count());
  row("sort", t.sort);
  row("P2G (+ stress force)", t.p2g);
  row("grid update", t.grid_update);
  row("G2P", t.g2p);
  row("stress + return map", t.stress);
  std::printf("  %-22s %8.3f s\n", "wall (incl. output)", wall);
  std::printf("throughput: %s particle-steps/s over the steps, peak memory %.1f MiB\n",
              Progress::format_rate(double(particles) * sim.step_count() / total).c_str(),
              peak_rss_mib());
}

// Frames the particles' bounding box, with the ground at the domain's floor wall.
void write_picture(const Simulation& sim, const std::string& path) {
  const Particles& P = sim.particles();
  const SimSettings& s = sim.settings();
  Vec3 lo = P.x[0], hi = P.x[0];
  for (const Vec3& x : P.x) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  RenderOptions opt;
  frame_box(opt, lo, hi);
  opt.radius = 0.5 * s.dx / s.ppc;
  opt.ground_height = std::min(lo[1], s.domain_lo[1] + s.wall_nodes * s.dx);
  write_png(render_particles(P.x, colors_by_index(P.object), opt), path);
}

void run_simulate(const SimulateArgs& a) {
  const int threads = set_threads(a.threads);
  Scene scene = load_scene(a.scene, a.overrides);
  const std::string name = scene.name;
  Simulation sim(std::move(scene));
  const SimSettings& s = sim.settings();
  const size_t np = sim.particles().size();
  std::fprintf(stderr, "nsf simulate: %s, %zu particles, grid %dx%dx%d, %d frames x %d steps, "
               "%d threads\n", name.c_str(), np, sim.grid().dims()[0], sim.grid().dims()[1],
               sim.grid().dims()[2], s.frames, s.substeps, threads);

  Progress progress("simulate", s.frames, "frames");
  const double start = now_seconds();
  run_to_file(sim, a.out, {}, [&](int f) {
    const double rate = double(np) * sim.step_count() / (now_seconds() - start);
    if (!a.quiet) progress.update(f, Progress::format_rate(rate) + " particle-steps/s");
  });
  const double wall = now_seconds() - start;
  if (!a.quiet) progress.finish();
  if (!a.png.empty()) {
    write_picture(sim, a.png);
    std::printf("picture: %s\n", a.png.c_str());
  }
  std::printf("wrote %s (%d frames, %zu particles)\n", a.out.c_str(), s.frames + 1, np);
  print_breakdown(sim, wall, np);
}

}  // namespace

void add_simulate_command(CLI::App& app) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* cmd = app.add_subcommand("simulate", "Run a full-order MPM simulation of a scene");
  cmd->add_option("scene", args->scene, "Scene JSON file")->required()->check(CLI::ExistingFile);
  cmd->add_option("--out,-o", args->out, "Output HDF5 file (docs/OUTPUT.md)")->required();
  cmd->add_option("--set", args->overrides, "Override a scene value, e.g. --set material.E=5")
      ->type_name("KEY=VALUE");
  cmd->add_option("--png", args->png, "Also write a picture of the last frame");
  cmd->add_option("--threads,-j", args->threads, "OpenMP threads (0 = all cores)")
      ->check(CLI::Range(0, 1024));
  cmd->add_flag("--quiet,-q", args->quiet, "No progress line");
  cmd->callback([args] { run_simulate(*args); });
}

}  // namespace nsf::app
