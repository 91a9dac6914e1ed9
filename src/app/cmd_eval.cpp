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
  std::printf("%-24s %12s %7s %10s %12s %12s\n", "run", "mu", "frames", "delta", "stress err",
              "affine err");
  double d = 0, s = 0, c = 0;
  for (const EvalRow& r : rows) {
    char mu[32] = "-";
    if (r.has_mu) std::snprintf(mu, sizeof mu, "%.6g", r.mu);
    std::printf("%-24s %12s %7zu %10s %12s %12s\n", r.run.c_str(), mu, r.frames,
                percent(r.delta).c_str(), percent(r.stress_error).c_str(),
                percent(r.affine_error).c_str());
    d += r.delta, s += r.stress_error, c += r.affine_error;
  }
  const double n = double(rows.size());
  std::printf("%-24s %12s %7s %10s %12s %12s\n", "mean", "", "", percent(d / n).c_str(),
              percent(s / n).c_str(), percent(c / n).c_str());
  std::printf(
      "(latents from the encoder on each ground-truth frame; %zu particles per frame; "
      "%.1f s)\n",
      rows.empty() ? size_t(0) : rows[0].particles, now_seconds() - start);
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
  cmd->add_option("--threads,-j", a->threads, "Threads (0 = all cores)")->capture_default_str();
  cmd->callback([a] { run_eval(*a); });
}

}  // namespace nsf::app
