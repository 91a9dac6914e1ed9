// `nsf simulate scene.json --out run.h5`: run the full-order engine and save every frame.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/common_options.h"
#include "core/error.h"
#include "core/memory.h"
#include "core/path_clash.h"
#include "core/progress.h"
#include "data/run_to_file.h"
#include "io/collider_shapes.h"
#include "io/image.h"
#include "io/legend.h"
#include "io/png_render.h"
#include "io/run_render.h"
#include "io/xdmf_writer.h"
#include "mpm/simulation.h"
#include "rom/setup/scene_file.h"

namespace nsf::app {

namespace {

struct SimulateArgs {
  std::string scene, out, png;
  std::vector<std::string> overrides;
  int threads = 0, gzip = 0;
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

// Where to draw the ground: the highest upward-facing plane collider, else the floor wall.
double floor_height(const Scene& scene) {
  const SimSettings& s = scene.settings;
  double h = s.domain_lo[1] + s.wall_nodes * s.dx;
  for (const auto& c : scene.source.value("colliders", nlohmann::json::array())) {
    if (c.value("type", "") != "plane" || !c.contains("normal")) continue;
    const Vec3 n(c["normal"][0].get<double>(), c["normal"][1].get<double>(),
                 c["normal"][2].get<double>());
    if (n.normalized()[1] > 0.99) h = std::max(h, c["point"][1].get<double>());
  }
  return h;
}

// A strip of snapshots (positions at chosen frames), one fixed camera framing all of them, the
// ground at the domain's floor wall, the colliders where they were, each panel labelled with
// its time.
void write_filmstrip(const Simulation& sim, const std::vector<std::vector<Vec3>>& snapshots,
                     const std::vector<double>& times, const std::string& path) {
  const SimSettings& s = sim.settings();
  Vec3 lo = snapshots[0][0], hi = lo;
  for (const auto& xs : snapshots)
    for (const Vec3& x : xs) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  RenderOptions opt;
  opt.width = 480, opt.height = 400;
  frame_box(opt, lo, hi);
  opt.radius = 0.5 * s.dx / s.ppc;
  opt.ground_height = floor_height(sim.scene());
  const auto colors = colors_by_index(sim.particles().object);
  const nlohmann::json& source = sim.scene().source;
  const SceneColliders colliders(source.value("colliders", nlohmann::json()));
  Image strip;
  for (size_t k = 0; k < snapshots.size(); ++k) {
    opt.colliders = colliders.at(times[k]);
    Image panel = render_particles(snapshots[k], colors, opt);
    char label[64];
    std::snprintf(label, sizeof label, "t = %.3f s", times[k]);
    const double size = text_size_for(opt.width, opt.height);
    draw_label(panel, label_margin(size), label_margin(size), label, size);
    strip = k == 0 ? panel : side_by_side(strip, panel);
  }
  write_png(strip, path);
}

void run_simulate(const SimulateArgs& a) {
  // The clash below would name "--out 'o.xdmf'", a path the user never gave as --out.
  if (same_file(xdmf_path_for(a.out), a.scene))
    fail("the scene argument '", a.scene, "' is the XDMF file nsf simulate writes beside --out '",
         a.out,
         "': writing it would destroy that input; give the scene's JSON file as the scene "
         "argument, or another --out");
  refuse_path_clash(
      {{"--out", a.out}, {"the XDMF sidecar of --out", xdmf_path_for(a.out)}, {"--png", a.png}},
      {{"the scene", a.scene}});
  const int threads = set_threads(a.threads);
  // The whole scene is checked, also the sections only other commands read
  // (rom/setup/scene_file.h).
  Scene scene = build_scene_file(read_scene_file(a.scene, a.overrides));
  const std::string name = scene.name;
  Simulation sim(std::move(scene));
  const SimSettings& s = sim.settings();
  const size_t np = sim.particles().size();
  std::fprintf(stderr,
               "nsf simulate: %s, %zu particles, grid %dx%dx%d, %d frames x %d steps, "
               "%d threads\n",
               name.c_str(), np, sim.grid().dims()[0], sim.grid().dims()[1], sim.grid().dims()[2],
               s.frames, s.substeps, threads);

  // Snapshots for the picture: the first frame, two in between, and the last.
  std::vector<std::vector<Vec3>> snapshots{sim.particles().x};
  std::vector<double> snapshot_times{sim.time()};
  Progress progress("simulate", s.frames, "frames");
  const double start = now_seconds();
  run_to_file(
      sim, a.out, {},
      [&](int f) {
        if (!a.png.empty() && (f == s.frames || f * 3 / s.frames != (f - 1) * 3 / s.frames)) {
          snapshots.push_back(sim.particles().x);
          snapshot_times.push_back(sim.time());
        }
        const double rate = double(np) * sim.step_count() / (now_seconds() - start);
        if (!a.quiet) progress.update(f, Progress::format_rate(rate) + " particle-steps/s");
      },
      RunWriterOptions{a.gzip});
  const double wall = now_seconds() - start;
  if (!a.quiet) progress.finish();
  if (!a.png.empty()) {
    write_filmstrip(sim, snapshots, snapshot_times, a.png);
    std::printf("picture: %s\n", a.png.c_str());
  }
  std::printf("wrote %s (%d frames, %zu particles)\n", a.out.c_str(), s.frames + 1, np);
  print_breakdown(sim, wall, np);
}

}  // namespace

void add_simulate_command(CLI::App& app) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* cmd = app.add_subcommand("simulate", "Run a full-order MPM simulation of a scene");
  cmd->add_option("scene", args->scene, "Scene JSON file")->required();
  cmd->add_option("--out,-o", args->out, "Output HDF5 file (docs/OUTPUT.md)")->required();
  cmd->add_option("--set", args->overrides, "Override a scene value, e.g. --set material.E=5")
      ->type_name("KEY=VALUE")
      ->check(override_syntax());
  cmd->add_option("--png", args->png, "Also write a picture: snapshots from start to end");
  add_threads_option(cmd, args->threads, "OpenMP threads");
  add_gzip_option(cmd, args->gzip);
  add_quiet_flag(cmd, args->quiet);
  cmd->callback([args] { run_simulate(*args); });
}

}  // namespace nsf::app
