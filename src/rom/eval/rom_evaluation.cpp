#include "rom/eval/rom_evaluation.h"

#include <malloc.h>
#include <omp.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <random>

#include "core/cpu_model.h"
#include "core/error.h"
#include "core/memory.h"
#include "core/progress.h"
#include "core/timer.h"
#include "io/run_reader.h"
#include "io/run_writer.h"
#include "io/xdmf_writer.h"
#include "mpm/simulation.h"
#include "nn/checked_archive.h"
#include "nn/field_checks.h"
#include "nn/torch_settings.h"
#include "rom/eval/baseline_inputs.h"
#include "rom/step/step_guard.h"

namespace nsf {

namespace {

// Removes a scratch file when the evaluation ends, however it ends.
struct ScratchFile {
  std::string path;
  ~ScratchFile() {
    if (path.empty()) return;
    std::error_code ec;  // a destructor does not throw; a file already gone is no matter
    std::filesystem::remove(path, ec);
    std::filesystem::remove(xdmf_path_for(path), ec);  // the run file's ParaView sidecar
  }
};

// k points per particle, jittered uniformly inside the particle's own rest cube (side V⁰^⅓),
// seeded: the resolution boost of Fig. 6 queries g at these instead of at the particles.
Particles upsampled_points(const Particles& P, int k) {
  Particles out;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  for (size_t p = 0; p < P.size(); ++p) {
    const double h = std::cbrt(P.vol0[p]);
    for (int i = 0; i < k; ++i) {
      const Vec3 X = P.X[p] + h * Vec3(u(rng), u(rng), u(rng));
      out.add(X, Vec3::Zero(), P.mass[p] / k, P.vol0[p] / k, P.mat[p], P.material[p], P.object[p]);
    }
  }
  return out;
}

// Checks that a ground-truth run is this scene and has a frame at every output time.
void check_truth(const RunReader& truth, const Scene& scene, int frames, double frame_dt) {
  if (truth.particle_count() != scene.particles.size() ||
      truth.rest_positions() != scene.particles.X)
    fail("rom: ground truth ", truth.path(), " holds ", truth.particle_count(),
         " particles with other rest positions than scene '", scene.name, "' (",
         scene.particles.size(), " particles): it is a run of another scene");
  if (truth.frame_count() < size_t(frames) + 1)
    fail("rom: ground truth ", truth.path(), " has ", truth.frame_count(),
         " frames, the scene needs ", frames + 1);
  for (int f = 0; f <= frames; ++f)
    if (std::abs(truth.times()[f] - f * frame_dt) > 1e-6 * std::max(1.0, f * frame_dt))
      fail("rom: ground truth ", truth.path(), " frame ", f, " is at t = ", truth.times()[f],
           " s, the scene's frame ", f, " at t = ", f * frame_dt, " s");
}

// What the report holds before either engine runs: the scene, the model and the settings.
void describe_setup(const RomEvalOptions& o, const NeuralFields& fields, const RomSetup& s,
                    RomReport& rep) {
  rep.scene = s.scene.name;
  rep.mu = s.mu;
  rep.has_mu = s.has_mu;
  rep.sweep_parameter = s.sweep_parameter;
  rep.dt_ratio = s.options.dt_ratio;
  rep.dt_ratio_source = s.dt_ratio_source;
  rep.latent_prior_source = s.latent_prior_source;
  rep.profile = s.profile;
  rep.outside_family = s.outside_family;
  rep.particles = s.scene.particles.size();
  rep.latent_dim = fields.latent_dim();
  rep.train_seconds = fields.train_seconds();
  rep.model_checksum = stored_checksum(o.model_path);
  rep.gamma = 3.0 * double(rep.particles) / rep.latent_dim;
  rep.frames = s.scene.settings.frames;
  rep.fom_steps_per_frame = s.scene.settings.substeps;
  rep.frame_dt = s.scene.settings.substeps * s.scene.settings.dt;
}

// Full order, frame by frame into `path`: the ground truth the ROM is measured against. The
// scene comes back at its initial state: materials hold no state and colliders take their pose
// from the time they are given, so the scene with its initial particles back is the scene as
// built.
void run_full_order(const RomEvalOptions& o, RomSetup& s, const std::string& path, RomReport& rep) {
  const SimSettings settings = s.scene.settings;
  rep.peak_reset = reset_peak_rss();
  Particles initial = s.scene.particles;
  Simulation sim(std::move(s.scene));
  RunWriter writer(path, sim.particles(), settings, rep.scene, s.json.dump(),
                   RunWriterOptions{o.gzip});
  if (rep.has_mu) {
    writer.set_attribute("mu", rep.mu);
    writer.set_attribute("sweep_parameter", rep.sweep_parameter);
  }
  writer.write_frame(sim.particles(), sim.time());
  Progress progress("full order", settings.frames, "frames");
  for (int f = 1; f <= settings.frames; ++f) {
    const double t0 = now_seconds();
    sim.advance_frame();
    rep.fom_seconds = std::max(0.0, rep.fom_seconds) + (now_seconds() - t0);
    writer.write_frame(sim.particles(), sim.time());
    if (!o.quiet) progress.update(f);
  }
  writer.finish();
  if (!o.quiet) progress.finish();
  rep.fom_peak_mib = peak_rss_mib();
  s.scene = std::move(sim).release_scene();
  s.scene.particles = std::move(initial);
}

// The ground truth: the full-order run made here (into o.fom_out, else a scratch file), else
// o.truth_path; none when neither.
std::unique_ptr<RunReader> ground_truth(const RomEvalOptions& o, RomSetup& s, ScratchFile& scratch,
                                        RomReport& rep) {
  std::string truth_path = o.truth_path;
  if (o.full_order) {
    std::string path = o.fom_out;
    if (path.empty()) {
      path = (std::filesystem::temp_directory_path() /
              ("nsf_rom_truth_" + std::to_string(getpid()) + ".h5"))
                 .string();
      scratch.path = path;
    }
    run_full_order(o, s, path, rep);
    if (truth_path.empty()) truth_path = path;
  }
  if (truth_path.empty()) return nullptr;
  if (!std::filesystem::exists(truth_path))
    fail("rom: ground-truth file ", truth_path, " does not exist");
  auto truth = std::make_unique<RunReader>(truth_path);
  check_truth(*truth, s.scene, s.scene.settings.frames, rep.frame_dt);
  rep.truth_file = truth_path;
  return truth;
}

// The ROM's run file, in the layout of `nsf simulate` plus its latents and what made it.
std::unique_ptr<RunWriter> rom_writer(const RomEvalOptions& o, const RomSetup& s,
                                      const SimSettings& settings, const Particles& points,
                                      const RomReport& rep) {
  auto writer = std::make_unique<RunWriter>(o.out_path, points, settings, rep.scene, s.json.dump(),
                                            RunWriterOptions{o.gzip});
  writer->set_attribute("rom", 1);
  // Absolute, so that the file still names its model when read from elsewhere.
  writer->set_attribute("rom_model",
                        std::filesystem::absolute(o.model_path).lexically_normal().string());
  writer->set_attribute("rom_fields",
                        "x and v from the neural deformation field, " + rep.field_sources +
                            " (what the ROM step uses, at each frame's latent); F is not "
                            "computed (identity); /rom/latent: the latent of each frame "
                            "(frames x r)");
  if (rep.has_mu) {
    writer->set_attribute("mu", rep.mu);
    writer->set_attribute("sweep_parameter", rep.sweep_parameter);
  }
  return writer;
}

// Each frame of the ROM: compared with the truth (δ of eq. 11 over frames 1…N, τ and C),
// written, and its online diagnostics (the inversion's residual, the distance to
// the training latents) averaged.
class FrameRecorder {
 public:
  FrameRecorder(const RomEvalOptions& o, LatentStepper& rom, const RunReader* truth,
                RunWriter* writer, Particles points, double dx, const NeuralFields& fields,
                RomReport& rep)
      : o_(o),
        rom_(rom),
        truth_(truth),
        writer_(writer),
        frame_(std::move(points)),
        dx_(dx),
        rep_(rep) {
    if (o.upsample > 1) boost_ = fields.prepare(frame_.X);
  }

  void record(int f) {
    const double t1 = now_seconds();
    rom_.particle_state(x_, &v_);
    const bool compare = truth_ && f > 0;
    if (compare || writer_) rom_.particle_fields(tau_, C_);
    if (compare) compare_with_truth(f);
    if (writer_) write();
    if (f > 0) add_diagnostics();
    rep_.rom_output_seconds += now_seconds() - t1;
  }

  // The latents of the written frames, into the run file, which is then complete.
  void finish() {
    if (!writer_) return;
    const size_t r = size_t(rom_.latent().size());
    writer_->write_table("/rom/latent", latents_.size() / r, r, latents_.data());
    writer_->finish();
  }

 private:
  void compare_with_truth(int f) {
    const RunFrame truth_frame = truth_->read_frame(size_t(f));
    const std::vector<Vec3>& phi = truth_frame.x;
    ErrorSum frame_delta;
    for (size_t p = 0; p < phi.size(); ++p) {
      frame_delta.add(x_[p], phi[p]);
      stress_.add(tau_[p], truth_frame.tau[p]);
      affine_.add(C_[p], truth_frame.C[p]);
    }
    rep_.delta_per_frame.push_back(frame_delta.relative());
    delta_.add(frame_delta);
    rep_.delta = delta_.relative();
    // < 0 for "not measured": a truth without stress (a rigid drop) has no relative error.
    rep_.stress_error = stress_.ref > 0 ? stress_.relative() : -1.0;
    rep_.affine_error = affine_.ref > 0 ? affine_.relative() : -1.0;
  }

  void write() {
    if (o_.upsample > 1) rom_.state(boost_, frame_.object, x_, &v_);
    frame_.x = x_;
    frame_.v = v_;
    // Upsampled points carry their particle's τ and C (point i comes from particle i / k).
    for (size_t i = 0; i < frame_.size(); ++i)
      frame_.tau[i] = tau_[i / size_t(o_.upsample)], frame_.C[i] = C_[i / size_t(o_.upsample)];
    writer_->write_frame(frame_, rom_.time());
    latents_.insert(latents_.end(), rom_.latent().data(),
                    rom_.latent().data() + rom_.latent().size());
  }

  void add_diagnostics() {
    const double cells = rom_.diagnostics().last_residual / dx_;
    rep_.residual_cells_max = std::max(rep_.residual_cells_max, cells);
    rep_.residual_cells_mean += cells / rep_.frames;
    if (const double d = rom_.diagnostics().training_distance; d >= 0) {
      rep_.training_distance_max = std::max(rep_.training_distance_max, d);
      rep_.training_distance_mean += d / rep_.frames;
    }
  }

  const RomEvalOptions& o_;
  LatentStepper& rom_;
  const RunReader* truth_;
  RunWriter* writer_;
  Particles frame_;
  double dx_;
  RomReport& rep_;
  NeuralFields::Points boost_;
  std::vector<Vec3> x_, v_;
  std::vector<Mat3> tau_, C_;
  std::vector<double> latents_;  // ẑ of every written frame, row by row
  ErrorSum delta_, stress_, affine_;
};

// The error budget's projection, on the ROM's own samples and with its fit (latent prior and
// rigid frames included), run to convergence on each frame.
std::unique_ptr<ErrorBudget> error_budget(NeuralFields& fields, const LatentStepper& rom,
                                          const RunReader* truth, double mu) {
  if (!truth) fail("rom: the error budget (--budget) needs a ground truth (--truth or full order)");
  GaussNewtonOptions gn = rom.inversion_options();
  gn.max_iterations = std::max(gn.max_iterations, kBudgetIterations);
  gn.taylor = false;
  return std::make_unique<ErrorBudget>(fields, truth->rest_positions(), rom.samples(), mu, gn,
                                       rom.latent(), &rom.rigid_frames());
}

// The error budget on the truth's frames 1…frames.
ErrorBudgetResult measure_budget(ErrorBudget& budget, const RunReader& truth, int frames,
                                 bool quiet) {
  Progress progress("error budget", frames, "frames");
  for (int f = 1; f <= frames; ++f) {
    const RunFrame t = truth.read_frame(size_t(f));
    budget.add_frame(t.x, t.v, t.tau, t.C);
    if (!quiet) progress.update(f);
  }
  if (!quiet) progress.finish();
  return budget.result();
}

// The frames of the ROM, timed step by step, each recorded.
void run_reduced_order(const RomEvalOptions& o, LatentStepper& rom, FrameRecorder& recorder,
                       RomReport& rep) {
  recorder.record(0);
  Progress progress("reduced order", rep.frames, "frames");
  std::optional<StepGuard> guard;
  if (o.guard) guard.emplace(rom);
  rep.guarded = o.guard;
  for (int f = 1; f <= rep.frames; ++f) {
    const double t0 = now_seconds();
    if (guard)
      guard->advance_frame();
    else
      rom.advance_frame();
    rep.rom_seconds += now_seconds() - t0;
    if (rep.training_note.empty()) rep.training_note = outside_training_box(rom);
    recorder.record(f);
    if (!o.quiet) {
      char extra[96];
      std::snprintf(extra, sizeof extra, "|N| %zu, delta %.2f%%",
                    rom.integration_particles().size(), rep.delta >= 0 ? 100 * rep.delta : 0.0);
      progress.update(f, extra);
    }
  }
  if (!o.quiet) progress.finish();
  recorder.finish();
  if (guard && guard->health().recoveries > 0) {
    rep.recoveries = guard->health().recoveries;
    rep.last_recovery = guard->health().last_recovery;
    rep.warnings.push_back("the step guard redid " + std::to_string(rep.recoveries) +
                           " step(s) that diverged or passed the error indicator's limits, as "
                           "the runtime does (--guard); the last, at " +
                           rep.last_recovery);
  }
  if (!rep.training_note.empty())
    rep.warnings.push_back("the run left the model's training box at " + rep.training_note +
                           ": the model may not hold what followed");
}

// What the ROM reports of itself once it ran.
void describe_rom(const LatentStepper& rom, const RomOptions& ro, RomReport& rep) {
  rep.samples_end = rom.sample_count();
  const RomDiagnostics d = rom.diagnostics();
  rep.mean_N = d.mean_N;
  rep.mean_K = d.mean_K;
  rep.energy_kept = d.energy_kept;
  rep.latent_prior = ro.latent_prior;
  rep.sampling = ro.sampling.mode;
  rep.sample_condition = d.sample_condition;
  if (d.training_distance < 0) rep.training_distance_mean = rep.training_distance_max = -1;
  if (const std::string w = latent_drift_warning(rep.training_distance_mean, ro.latent_prior);
      !w.empty())
    rep.warnings.push_back(w);
  rep.quadrature_points = d.quadrature_points;
  rep.quadrature_per_cell = ro.quadrature_per_cell;
  rep.grid_factor = ro.grid_factor;
  rep.refreshes = d.refreshes;
  rep.rom_times = d.times;
}

RomSettingChoices setting_choices(const RomEvalOptions& o) {
  RomSettingChoices c;
  c.rom = o.rom;
  c.dt_ratio = o.dt_ratio, c.latent_prior = o.latent_prior, c.quadrature = o.quadrature;
  c.gn_iterations = o.gn_iterations, c.samples = o.samples, c.seed = o.seed;
  c.profile = o.profile;
  return c;
}

}  // namespace

RomReport evaluate_rom(const RomEvalOptions& o) {
  RomReport rep;
  if (o.upsample < 1) fail("rom: --upsample must be at least 1, got ", o.upsample);
  // 0 is all cores (OMP_NUM_THREADS where set), the same count for OpenMP and the networks.
  rep.threads = o.threads > 0 ? o.threads : omp_get_max_threads();
  rep.cpu = cpu_model();
  omp_set_num_threads(rep.threads);
  set_nn_threads(rep.threads);
  NeuralFields fields = NeuralFields::load(o.model_path);
  RomSetup s = rom_setup(fields, o.model_path, read_scene_file(o.scene_path, o.overrides), o.mu,
                         setting_choices(o));
  if (o.print_warnings)
    for (const std::string& w : s.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  rep.warnings = s.warnings;
  const BaselineInputs baseline_inputs = read_baseline_inputs(o, s);
  if (!baseline_inputs.coarse_skipped.empty())
    rep.warnings.push_back(baseline_inputs.coarse_skipped);
  if (!baseline_inputs.coarse_note.empty()) rep.warnings.push_back(baseline_inputs.coarse_note);
  describe_setup(o, fields, s, rep);
  // Memory a caller freed before (training in `nsf report`, say) goes back to the system first,
  // so that it does not sit in the baseline and hide each phase's own peak.
  malloc_trim(0);
  rep.baseline_mib = current_rss_mib();

  ScratchFile scratch;
  const std::unique_ptr<RunReader> truth = ground_truth(o, s, scratch, rep);
  if (o.full_order) {
    malloc_trim(0);
    reset_peak_rss();
  }
  Particles points =
      o.upsample > 1 ? upsampled_points(s.scene.particles, o.upsample) : s.scene.particles;
  rep.output_points = points.size();
  const SimSettings settings = s.scene.settings;  // the scene moves into the stepper
  const double t0 = now_seconds();
  LatentStepper rom(fields, std::move(s.scene), rep.mu, s.options);
  rep.rom_setup_seconds = now_seconds() - t0;
  rep.rom_steps_per_frame = rom.steps_per_frame();
  if (s.options.dt_ratio == RomOptions::kDtRatioAtCfl)
    rep.dt_ratio = double(rep.fom_steps_per_frame) / rep.rom_steps_per_frame,
    rep.dt_ratio_source += ", at the CFL bound";
  rep.samples = rom.sample_count();
  rep.field_sources = rom.diagnostics().field_sources;
  const std::unique_ptr<ErrorBudget> budget =
      o.budget ? error_budget(fields, rom, truth.get(), rep.mu) : nullptr;
  const std::unique_ptr<RunWriter> writer =
      o.out_path.empty() ? nullptr : rom_writer(o, s, settings, points, rep);
  FrameRecorder recorder(o, rom, truth.get(), writer.get(), std::move(points), settings.dx, fields,
                         rep);
  run_reduced_order(o, rom, recorder, rep);
  rep.rom_file = o.out_path;
  rep.rom_peak_mib = peak_rss_mib();
  describe_rom(rom, s.options, rep);
  // The budget after the run, so that neither the ROM's time nor its memory holds its work.
  if (budget) rep.budget = measure_budget(*budget, *truth, rep.frames, o.quiet);

  // The baselines, after the ROM so that its peak memory is its own.
  if (!baseline_inputs.runs.empty())
    measure_sweep_baselines(baseline_inputs.runs, rep.mu, *truth, rep.frames, rep.baselines,
                            o.axes);
  if (baseline_inputs.coarse) {
    measure_coarse_baseline(*baseline_inputs.coarse, baseline_inputs.coarse_json, *truth,
                            rep.frames, rep.threads, o.quiet, rep.baselines);
    rep.baselines.coarse_scene = baseline_inputs.label;
  }
  return rep;
}

}  // namespace nsf
