// `nsf eval models/NAME.nsf data/NAME`: δ (eq. 11), stress and affine errors per test run.
#include <cmath>
#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/common_options.h"
#include "core/path_clash.h"
#include "core/timer.h"
#include "io/atomic_file.h"
#include "nn/basis_decoders.h"
#include "nn/evaluate.h"
#include "nn/neural_fields.h"
#include "nn/torch_settings.h"

namespace nsf::app {

namespace {

struct EvalArgs {
  std::string model, data, json;
  EvalOptions opt;
  int threads = 0;
  bool quiet = false;  // accepted, as by every command: eval prints no progress
};

std::string percent(double v) {
  if (std::isnan(v)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f%%", 100.0 * v);
  return buf;
}

// NaN (a field that is zero throughout) as JSON null.
nlohmann::json number(double v) {
  return std::isnan(v) ? nlohmann::json() : nlohmann::json(v);
}

// Means over the runs of the held-out particles' errors (--held-out-particles).
nlohmann::json held_out_json(const EvalArgs& a, const std::vector<EvalRow>& rows) {
  auto mean_of = [&](double HeldOutErrors::*field) {
    double s = 0;
    for (const EvalRow& r : rows) s += r.held_out.*field;
    return number(rows.empty() ? NAN : s / double(rows.size()));
  };
  return {{"stride", a.opt.held_out_stride},
          {"particles", rows.empty() ? 0 : rows[0].held_out.particles},
          {"interpolation", a.opt.interpolation},
          {"neighbours", a.opt.neighbours},
          {"delta", mean_of(&HeldOutErrors::delta)},
          {"stress_error", mean_of(&HeldOutErrors::stress)},
          {"affine_error", mean_of(&HeldOutErrors::affine)},
          {"at_particles",
           {{"delta", mean_of(&HeldOutErrors::own_delta)},
            {"stress_error", mean_of(&HeldOutErrors::own_stress)},
            {"affine_error", mean_of(&HeldOutErrors::own_affine)}}}};
}

// One run's errors; a basis model's with the projection bound beside them.
nlohmann::json run_json(const EvalRow& r, bool basis) {
  nlohmann::json run = {{"run", r.run},
                        {"frames", r.frames},
                        {"delta", number(r.delta)},
                        {"delta_encoded", number(r.delta_encoded)},
                        {"stress_error", number(r.stress_error)},
                        {"affine_error", number(r.affine_error)},
                        {"force_error", number(r.force_error)}};
  if (r.has_mu) run["mu"] = r.mu;
  if (basis)
    run["projection_bound"] = {{"delta", number(r.projection_delta)},
                               {"stress_error", number(r.projection_stress)},
                               {"affine_error", number(r.projection_affine)}};
  return run;
}

// The machine-readable row (docs/results/eval/SCENE_DECODER.json): means over the runs, as the
// table's last line prints them, and each run's own.
void write_json(const EvalArgs& a, const std::vector<EvalRow>& rows) {
  const NeuralFields nf = NeuralFields::load(a.model);
  auto mean = [&](double EvalRow::*field) {
    double s = 0;
    for (const EvalRow& r : rows) s += r.*field;
    return number(rows.empty() ? NAN : s / double(rows.size()));
  };
  nlohmann::json j;
  j["scene"] = nf.scene_name();
  j["decoder"] = nf.decoder();
  if (const BasisDecoders* b = nf.bases())  // how τ's and C's coefficients are made
    j["coefficients"] = {{"tau", b->tau.map.empty() ? "network" : "map"},
                         {"C", b->C.map.empty() ? "network" : "map"},
                         {"affine_reads_velocity", b->affine_uses_velocity},
                         {"stress_reads_velocity", b->stress_uses_velocity}};
  j["model"] = a.model;
  j["data"] = a.data;
  j["split"] = a.opt.split;
  j["latent_dim"] = nf.latent_dim();
  j["refine_iterations"] = a.opt.refine_iterations;
  j["delta"] = mean(&EvalRow::delta);
  j["delta_encoded"] = mean(&EvalRow::delta_encoded);
  j["stress_error"] = mean(&EvalRow::stress_error);
  j["affine_error"] = mean(&EvalRow::affine_error);
  j["force_error"] = mean(&EvalRow::force_error);
  j["train_seconds"] = nf.train_seconds();
  if (nf.bases())
    j["projection_bound"] = {{"delta", mean(&EvalRow::projection_delta)},
                             {"stress_error", mean(&EvalRow::projection_stress)},
                             {"affine_error", mean(&EvalRow::projection_affine)}};
  std::string held;
  if (a.opt.held_out_stride > 0) {
    j["held_out"] = held_out_json(a, rows);
    held = " --held-out-particles " + std::to_string(a.opt.held_out_stride) + " --interpolation " +
           a.opt.interpolation + " --neighbours " + std::to_string(a.opt.neighbours);
  }
  j["command"] =
      "nsf eval " + a.model + " " + a.data +
      (a.opt.refine_iterations > 0 ? " --refine " + std::to_string(a.opt.refine_iterations)
                                   : std::string()) +
      held + " --json " + a.json;
  for (const EvalRow& r : rows) j["runs"].push_back(run_json(r, nf.bases() != nullptr));
  write_file_atomic(a.json, j.dump(2) + "\n");
}

// The table of each run's errors and their means.
void print_table(const std::vector<EvalRow>& rows) {
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
}

// What the columns mean, and the bounds beside them: a basis model's projection, and the
// held-out particles' errors.
void print_notes(const EvalArgs& a, const std::vector<EvalRow>& rows, double seconds) {
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
      latents, rows.empty() ? size_t(0) : rows[0].particles, seconds, a.opt.poly_degree);
  if (!rows.empty() && !std::isnan(rows[0].projection_delta)) {
    double pd = 0, ps = 0, pa = 0;
    for (const EvalRow& r : rows)
      pd += r.projection_delta, ps += r.projection_stress, pa += r.projection_affine;
    const double n = double(rows.size());
    std::printf(
        "projection onto the model's bases (the best any coefficients can do): delta %s, "
        "stress %s, affine %s\n",
        percent(pd / n).c_str(), percent(ps / n).c_str(), percent(pa / n).c_str());
  }
  if (!rows.empty() && rows[0].held_out.particles > 0) {
    double d = 0, s = 0, c = 0, od = 0, os = 0, oc = 0;
    for (const EvalRow& r : rows) {
      const HeldOutErrors& h = r.held_out;
      d += h.delta, s += h.stress, c += h.affine, od += h.own_delta, os += h.own_stress,
          oc += h.own_affine;
    }
    const double n = double(rows.size());
    std::printf(
        "held-out particles (every %zu-th, %zu of them; %s over %d particles): read from the "
        "others delta %s, stress %s, affine %s; the model at those particles delta %s, stress "
        "%s, affine %s\n",
        a.opt.held_out_stride, rows[0].held_out.particles, a.opt.interpolation.c_str(),
        a.opt.neighbours, percent(d / n).c_str(), percent(s / n).c_str(), percent(c / n).c_str(),
        percent(od / n).c_str(), percent(os / n).c_str(), percent(oc / n).c_str());
  }
}

void run_eval(const EvalArgs& a) {
  set_nn_threads(a.threads);
  const double start = now_seconds();
  const auto rows = evaluate_model(a.model, a.data, a.opt);
  print_table(rows);
  print_notes(a, rows, now_seconds() - start);
  if (!a.json.empty()) {
    write_json(a, rows);
    std::printf("wrote %s\n", a.json.c_str());
  }
}

}  // namespace

void add_eval_command(CLI::App& app) {
  auto a = std::make_shared<EvalArgs>();
  CLI::App* cmd = app.add_subcommand(
      "eval", "Errors of a trained model on a dataset's runs: delta (eq. 11), stress, affine");
  cmd->add_option("model", a->model, "Model file (nsf train)")->required();
  cmd->add_option("data", a->data, "Dataset directory")->required();
  cmd->add_option("--split", a->opt.split, "test, train or all")
      ->capture_default_str()
      ->check(CLI::IsMember({"test", "train", "all"}));
  cmd->add_option("--every", a->opt.frame_stride, "Use every k-th frame")
      ->capture_default_str()
      ->check(in_range<long>(1, 1000000));
  cmd->add_option("--particles", a->opt.max_particles,
                  "Evaluate an evenly spaced subset of this many particles (0 = all)")
      ->capture_default_str()
      ->check(in_range<long>(0, 1000000000));
  cmd->add_option("--refine", a->opt.refine_iterations,
                  "Refine each encoded latent by this many Gauss-Newton iterations on 1,024 "
                  "particles, as the ROM's inversion would (0 = off)")
      ->capture_default_str()
      ->check(in_range(0, 100));
  cmd->add_option("--poly-degree", a->opt.poly_degree,
                  "Degree of the per-frame polynomial fits (poly columns)")
      ->capture_default_str()
      ->check(in_range(0, 8));
  cmd->add_option("--held-out-particles", a->opt.held_out_stride,
                  "Basis models: hold out every k-th particle and read its fields from the "
                  "others (the error at points that are not particles; 0 = off)")
      ->capture_default_str()
      ->check(in_range<long>(0, 1000000));
  cmd->add_option("--interpolation", a->opt.interpolation,
                  "How --held-out-particles reads between particles: mls or nearest")
      ->capture_default_str()
      ->check(CLI::IsMember({"mls", "nearest"}));
  cmd->add_option("--neighbours", a->opt.neighbours,
                  "Particles the interpolation of --held-out-particles reads from")
      ->capture_default_str()
      ->check(in_range(1, 1000));
  cmd->add_option("--json", a->json,
                  "Also write the means and each run's row as JSON (docs/results/eval/)");
  add_threads_option(cmd, a->threads);
  add_quiet_flag(cmd, a->quiet, "Accepted as by every command; eval prints no progress");
  cmd->add_flag("--allow-incomplete", a->opt.allow_incomplete,
                "Evaluate on a dataset an interrupted or partial sweep left incomplete, with a "
                "warning, instead of refusing it");
  cmd->callback([a] {
    refuse_path_clash({{"--json", a->json}}, {{"the model", a->model}});
    run_eval(*a);
  });
}

}  // namespace nsf::app
