// Full-order throughput benchmark (docs/BENCHMARKS.md): particle-steps per second at a fixed
// thread count on three scenes, with the per-phase breakdown and peak memory. Each scene runs in
// its own child process so its peak memory is its own.
#include <omp.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/memory.h"
#include "core/progress.h"
#include "core/timer.h"
#include "mpm/simulation.h"

namespace {

struct BenchScene {
  std::string label, file;
  int steps;
};

struct Result {
  double particles, steps, wall, sort, p2g, grid, g2p, stress, peak_mib;
};

Result run_scene(const BenchScene& b) {
  nsf::Scene scene = nsf::load_scene(std::string(NSF_SOURCE_DIR) + "/" + b.file);
  nsf::Simulation sim(std::move(scene));
  sim.step();  // warm-up step: first-touch of the grid and caches
  const nsf::StepTimes before = sim.times();
  nsf::Progress progress(b.label, b.steps, "steps");
  const double t0 = nsf::now_seconds();
  for (int i = 0; i < b.steps; ++i) {
    sim.step();
    progress.update(i + 1);
  }
  const double wall = nsf::now_seconds() - t0;
  const nsf::StepTimes& t = sim.times();
  return {double(sim.particles().size()),
          double(b.steps),
          wall,
          t.sort.seconds() - before.sort.seconds(),
          t.p2g.seconds() - before.p2g.seconds(),
          t.grid_update.seconds() - before.grid_update.seconds(),
          t.g2p.seconds() - before.g2p.seconds(),
          t.stress.seconds() - before.stress.seconds(),
          nsf::peak_rss_mib()};
}

// Runs one scene in a child process and returns its result through a pipe.
bool run_isolated(const BenchScene& b, Result* out) {
  int fd[2];
  if (pipe(fd) != 0) return false;
  pid_t pid = fork();
  if (pid == 0) {
    close(fd[0]);
    try {
      Result r = run_scene(b);
      if (write(fd[1], &r, sizeof r) != sizeof r) _exit(3);
      _exit(0);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench: %s: %s\n", b.label.c_str(), e.what());
      _exit(1);
    }
  }
  close(fd[1]);
  ssize_t got = read(fd[0], out, sizeof *out);
  close(fd[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  return got == sizeof *out && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"nsf full-order MPM throughput benchmark"};
  int threads = 2;
  double step_scale = 1.0;
  app.add_option("--threads,-j", threads, "OpenMP threads")->check(CLI::Range(1, 1024));
  app.add_option("--step-scale", step_scale, "Multiply each scene's step count (quick runs)")
      ->check(CLI::Range(0.01, 100.0));
  CLI11_PARSE(app, argc, argv);
  omp_set_num_threads(threads);

  const std::vector<BenchScene> scenes = {
      {"(a) reference block 64k", "scenes/examples/reference_block.json", 500},
      {"(b) elastic block 100k", "scenes/bench/elastic_block_100k.json", 300},
      {"(c) sand column 70k", "scenes/bench/sand_column_70k.json", 300},
  };
  std::printf("threads: %d, double precision\n\n", threads);
  std::printf(
      "| scene | particles | steps | particle-steps/s | sort | P2G | grid | G2P | "
      "stress+return map | peak memory |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  int failures = 0;
  for (BenchScene b : scenes) {
    b.steps = std::max(1, int(b.steps * step_scale));
    Result r;
    if (!run_isolated(b, &r)) {
      std::printf("| %s | failed | | | | | | | | |\n", b.label.c_str());
      ++failures;
      continue;
    }
    const double phases = r.sort + r.p2g + r.grid + r.g2p + r.stress;
    auto pct = [&](double x) { return 100.0 * x / phases; };
    std::printf(
        "| %s | %.0f | %.0f | %s | %.0f%% | %.0f%% | %.0f%% | %.0f%% | %.0f%% | %.0f MiB |\n",
        b.label.c_str(), r.particles, r.steps,
        nsf::Progress::format_rate(r.particles * r.steps / r.wall).c_str(), pct(r.sort), pct(r.p2g),
        pct(r.grid), pct(r.g2p), pct(r.stress), r.peak_mib);
    std::fflush(stdout);
  }
  return failures == 0 ? 0 : 1;
}
