// `nsf eval models/NAME.nsf data/NAME`: δ (eq. 11), stress and affine errors per test run.
#include <cmath>
#include <cstdio>
#include <string>

#include "app/commands.h"
#include "core/timer.h"
#include "nn/evaluate.h"
#include "nn/runtime.h"

namespace nsf::app {

namespace {

struct EvalArgs {
  std::string model, data;
  EvalOptions opt;
  int threads = 0;
};

std::string percent(double v) {
  if (std::isnan(v)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f%%", 100.0 * v);
  return buf;
}

void run_eval(const EvalArgs& a) {
  set_nn_threads(a.threads);
  const double start = now_seconds();
  const auto rows = evaluate_model(a.model, a.data, a.opt);
  std::printf("%-16s %9s %6s %8s | %8s %8s %8s | %8s %8s\n", "run", "mu", "frames", "delta",
              "stress", "poly", "force", "affine", "poly");
  double d = 0, s = 0, sf = 0, f = 0, c = 0, cf = 0;
  for (const EvalRow& r : rows) {
    char mu[32] = "-";
    if (r.has_mu) std::snprintf(mu, sizeof mu, "%.6g", r.mu);
    std::printf("%-16s %9s %6zu %8s | %8s %8s %8s | %8s %8s\n", r.run.c_str(), mu, r.frames,
                percent(r.delta).c_str(), percent(r.stress_error).c_str(),
                percent(r.stress_poly_fit).c_str(), percent(r.force_error).c_str(),
                percent(r.affine_error).c_str(), percent(r.affine_poly_fit).c_str());
    d += r.delta, s += r.stress_error, sf += r.stress_poly_fit, f += r.force_error;
    c += r.affine_error, cf += r.affine_poly_fit;
  }
  const double n = double(rows.size());
  std::printf("%-16s %9s %6s %8s | %8s %8s %8s | %8s %8s\n", "mean", "", "", percent(d / n).c_str(),
              percent(s / n).c_str(), percent(sf / n).c_str(), percent(f / n).c_str(),
              percent(c / n).c_str(), percent(cf / n).c_str());
  char latents[96] = "latents from the encoder";
  if (a.opt.refine_iterations > 0)
    std::snprintf(latents, sizeof latents,
                  "encoder latents refined by %d Gauss-Newton iterations on positions",
                  a.opt.refine_iterations);
  std::printf(
      "(%s on each ground-truth frame; %zu particles per frame; %.1f s)\n"
      "delta: eq. 11. stress, affine: relative error of h and l per particle. poly: residual of\n"
      "the best per-frame polynomial of degree %d in X per object, fitted to the ground truth "
      "(how\n"
      "much of the field is smooth at that scale; particle-scale noise stays). force: relative\n"
      "error of the grid forces -sum V tau grad w from h's stress, what the MPM step uses.\n",
      latents, rows.empty() ? size_t(0) : rows[0].particles, now_seconds() - start,
      a.opt.poly_degree);
}

}  // namespace

void add_eval_command(CLI::App& app) {
  auto a = std::make_shared<EvalArgs>();
  CLI::App* cmd = app.add_subcommand(
      "eval", "Errors of a trained model on a dataset's runs: delta (eq. 11), stress, affine");
  cmd->add_option("model", a->model, "Model file (nsf train)")->required();
  cmd->add_option("data", a->data, "Dataset directory")->required();
  cmd->add_option("--split", a->opt.split, "test, train or all")->capture_default_str();
  cmd->add_option("--every", a->opt.frame_stride, "Use every k-th frame")->capture_default_str();
  cmd->add_option("--particles", a->opt.max_particles,
                  "Evaluate an evenly spaced subset of this many particles (0 = all)")
      ->capture_default_str();
  cmd->add_option("--refine", a->opt.refine_iterations,
                  "Refine each encoded latent by this many Gauss-Newton iterations on 1,024 "
                  "particles, as the ROM's inversion would (0 = off)")
      ->capture_default_str()
      ->check(CLI::Range(0, 100));
  cmd->add_option("--poly-degree", a->opt.poly_degree,
                  "Degree of the per-frame polynomial fits (poly columns)")
      ->capture_default_str()
      ->check(CLI::Range(0, 8));
  cmd->add_option("--threads,-j", a->threads, "Threads (0 = all cores)")->capture_default_str();
  cmd->callback([a] { run_eval(*a); });
}

}  // namespace nsf::app
