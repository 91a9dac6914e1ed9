#include "app/rom_run.h"

#include <malloc.h>
#include <omp.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <sstream>

#include "app/scene_file.h"
#include "core/cpu_model.h"
#include "core/error.h"
#include "core/memory.h"
#include "core/progress.h"
#include "io/run_reader.h"
#include "io/run_writer.h"
#include "io/xdmf_writer.h"
#include "mpm/simulation.h"
#include "nn/checked_archive.h"
#include "nn/dataset.h"
#include "nn/field_checks.h"
#include "nn/runtime.h"

namespace nsf {

namespace {

// Removes a scratch file when the run ends, however it ends.
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

// Makes the scene JSON of the run: the file's (overrides applied), then μ through the scene's
// sweep templates.
nlohmann::json scene_at_mu(const RomRunOptions& o, const app::SceneFile& file,
                           const NeuralFields& fields, RomReport& rep) {
  nlohmann::json js = file.json;
  if (file.sections.sweep) {
    const SweepSpec& spec = *file.sections.sweep;
    if (!o.mu)
      fail("rom: scene ", o.scene_path, " varies '", spec.parameter, "' over [", spec.lo, ", ",
           spec.hi, "]; give its value with --mu");
    apply_overrides(js, sweep_overrides(spec, *o.mu));
    rep.mu = *o.mu;
    rep.has_mu = true;
    rep.sweep_parameter = spec.parameter;
    if (*o.mu < fields.mu_min() || *o.mu > fields.mu_max()) {
      std::ostringstream w;
      w << "mu = " << *o.mu << " lies outside the training range [" << fields.mu_min() << ", "
        << fields.mu_max() << "] of " << o.model_path
        << ": this is extrapolation, expect larger errors";
      rep.warnings.push_back(w.str());
      std::fprintf(stderr, "warning: %s\n", w.str().c_str());
    }
  } else if (o.mu) {
    fail("rom: --mu given, but scene ", o.scene_path,
         " has no \"sweep\" section saying what mu is");
  } else if (fields.stress_uses_mu()) {
    fail("rom: the model's stress field takes mu, but scene ", o.scene_path,
         " has no \"sweep\" section to set it");
  }
  return js;
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

// The baselines' inputs, read before any long run so that a bad one stops it at once.
struct BaselineInputs {
  std::vector<TrainingRun> runs;  // look-up and interpolation; empty: not asked for
  std::optional<app::SceneFile> coarse;
  nlohmann::json coarse_json;  // at μ
  std::string label;           // what the coarse engine runs, for the report
  std::string coarse_skipped;  // why the coarse engine is not measured (coarse_optional)
};

// The coarse engine's scene at μ, built once so that a scene it cannot build fails now.
void read_coarse_scene(const RomRunOptions& o, const RomReport& rep, BaselineInputs& in) {
  const std::string path = o.coarse_scene.empty() ? o.scene_path : o.coarse_scene;
  std::vector<std::string> overrides = o.overrides;  // the same case on the coarse scene
  if (o.coarse_factor > 0) {
    const std::vector<std::string> coarser =
        coarser_overrides(app::read_scene_file(path, overrides).json, o.coarse_factor);
    overrides.insert(overrides.end(), coarser.begin(), coarser.end());
  }
  in.coarse = app::read_scene_file(path, overrides);
  in.coarse_json = in.coarse->json;
  in.label = in.coarse_json.value("name", path);
  if (o.coarse_factor > 0) {
    char at[48];
    std::snprintf(at, sizeof at, " at %gx dx", o.coarse_factor);
    in.label += at;
  }
  if (rep.has_mu) {
    if (!in.coarse->sections.sweep)
      fail("rom: the coarse scene ", path, " has no \"sweep\" section to set mu");
    apply_overrides(in.coarse_json, sweep_overrides(*in.coarse->sections.sweep, rep.mu));
  }
  app::build_scene_file(*in.coarse, in.coarse_json);  // fails now on a scene it cannot build
}

BaselineInputs read_baseline_inputs(const RomRunOptions& o, const RomReport& rep,
                                    const Scene& scene) {
  BaselineInputs in;
  if (o.baseline_data.empty() && o.coarse_scene.empty() && o.coarse_factor == 0) return in;
  if (!o.full_order && o.truth_path.empty())
    fail("rom: the baselines need a ground truth (--truth, or the full-order run)");
  if (!o.baseline_data.empty()) {
    const Dataset data(o.baseline_data);
    if (!rep.has_mu || !data.has_mu())
      fail("rom: look-up and interpolation (--baselines ", o.baseline_data,
           ") need runs at other values of the scene's swept parameter mu");
    if (data.rest_positions() != scene.particles.X)
      fail("rom: dataset ", o.baseline_data, " is not scene ", o.scene_path,
           " (other particles): its runs cannot stand in for this one");
    for (const SimulationFile& s : data.train()) in.runs.push_back({s.path, s.mu});
    if (in.runs.size() < 2)
      fail("rom: dataset ", o.baseline_data, " has ", in.runs.size(),
           " training runs; look-up and interpolation need at least two");
  }
  if (!o.coarse_scene.empty() || o.coarse_factor > 0) {
    try {
      read_coarse_scene(o, rep, in);
    } catch (const Error& e) {
      if (!o.coarse_optional) throw;
      in.coarse.reset();
      in.coarse_skipped = std::string("coarse engine not measured: ") + e.what();
    }
  }
  return in;
}

}  // namespace

RomReport run_rom(const RomRunOptions& o) {
  RomReport rep;
  if (o.upsample < 1) fail("rom: --upsample must be at least 1, got ", o.upsample);
  // 0 is all cores (OMP_NUM_THREADS where set), the same count for OpenMP and the networks.
  const int threads = o.threads > 0 ? o.threads : omp_get_max_threads();
  omp_set_num_threads(threads);
  set_nn_threads(threads);
  NeuralFields fields = NeuralFields::load(o.model_path);
  const app::SceneFile file = app::read_scene_file(o.scene_path, o.overrides);
  const nlohmann::json js = scene_at_mu(o, file, fields, rep);
  // Built once: the full-order run borrows it and hands it back at its initial state.
  Scene scene = app::build_scene_file(file, js);
  fields.check_scene(scene.name, scene.particles.X, "scene " + o.scene_path);
  const BaselineInputs baseline_inputs = read_baseline_inputs(o, rep, scene);
  if (!baseline_inputs.coarse_skipped.empty())
    rep.warnings.push_back(baseline_inputs.coarse_skipped);

  // The scene's rom section (ε and the step: else the model's calibration), the tracked state's
  // own settings and calibration where the run carries it, then what the command line gave.
  const RomSection& scene_rom = file.sections.rom;
  const ModelCalibration calibrated = calibration_of(fields, scene_rom, o.rom.fields.stress);
  const RomSection& section = scene_rom.for_run(fields.decoder(), o.rom.fields.stress);
  if (file.json.contains("rom"))
    for (std::string& w :
         overrides_hidden_by_family(file.json.at("rom"), fields.decoder(), o.overrides))
      rep.warnings.push_back(std::move(w));
  RomOptions ro = with_rom_section(o.rom, section, calibrated);
  if (o.dt_ratio) ro.dt_ratio = *o.dt_ratio;
  if (o.latent_prior) ro.latent_prior = *o.latent_prior;
  const RomSettingSources sources =
      rom_setting_sources(section, calibrated, o.latent_prior.has_value(), o.dt_ratio.has_value());
  rep.dt_ratio = ro.dt_ratio;
  rep.dt_ratio_source = sources.dt_ratio;
  rep.latent_prior_source = sources.latent_prior;
  if (o.quadrature) ro.quadrature_per_cell = *o.quadrature;
  if (o.gn_iterations) ro.inversion.max_iterations = *o.gn_iterations;
  if (o.samples) ro.sampling.count = *o.samples;
  if (o.seed) ro.sampling.seed = *o.seed;

  const SimSettings settings = scene.settings;
  const double frame_dt = settings.substeps * settings.dt;
  rep.scene = scene.name;
  rep.particles = scene.particles.size();
  rep.latent_dim = fields.latent_dim();
  rep.train_seconds = fields.train_seconds();
  rep.model_checksum = stored_checksum(o.model_path);
  rep.gamma = 3.0 * double(rep.particles) / rep.latent_dim;
  rep.frames = settings.frames;
  rep.fom_steps_per_frame = settings.substeps;
  rep.frame_dt = frame_dt;
  // Memory a caller freed before (training in `nsf report`, say) goes back to the system first,
  // so that it does not sit in the baseline and hide each phase's own peak.
  malloc_trim(0);
  rep.baseline_mib = current_rss_mib();

  // Full order first: its file is the ground truth the ROM is measured against frame by frame.
  ScratchFile scratch;
  std::string truth_path = o.truth_path;
  if (o.full_order) {
    std::string path = o.fom_out;
    if (path.empty()) {
      path = (std::filesystem::temp_directory_path() /
              ("nsf_rom_truth_" + std::to_string(getpid()) + ".h5"))
                 .string();
      scratch.path = path;
    }
    rep.peak_reset = reset_peak_rss();
    Particles initial = scene.particles;
    Simulation sim(std::move(scene));
    RunWriter writer(path, sim.particles(), settings, rep.scene, js.dump(),
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
    if (truth_path.empty()) truth_path = path;
    // Materials hold no state and colliders take their pose from the time they are given, so
    // the scene with its initial particles back is the scene as built.
    scene = std::move(sim).release_scene();
    scene.particles = std::move(initial);
  }
  std::unique_ptr<RunReader> truth;
  if (!truth_path.empty()) {
    if (!std::filesystem::exists(truth_path))
      fail("rom: ground-truth file ", truth_path, " does not exist");
    truth = std::make_unique<RunReader>(truth_path);
    check_truth(*truth, scene, settings.frames, frame_dt);
    rep.truth_file = truth_path;
  }

  // The reduced-order run.
  if (o.full_order) {
    malloc_trim(0);
    reset_peak_rss();
  }
  const Particles out_points =
      o.upsample > 1 ? upsampled_points(scene.particles, o.upsample) : scene.particles;
  rep.output_points = out_points.size();
  double t0 = now_seconds();
  LatentStepper rom(fields, std::move(scene), rep.mu, ro);
  rep.rom_setup_seconds = now_seconds() - t0;
  rep.rom_steps_per_frame = rom.steps_per_frame();
  rep.samples = rom.sample_count();
  const NeuralFields::Points boost =
      o.upsample > 1 ? fields.prepare(out_points.X) : NeuralFields::Points();
  std::unique_ptr<ErrorBudget> budget;
  if (o.budget) {
    if (!truth)
      fail("rom: the error budget (--budget) needs a ground truth (--truth or full order)");
    GaussNewtonOptions gn = rom.inversion_options();  // the ROM's fit, latent prior included
    gn.max_iterations = std::max(gn.max_iterations, kBudgetIterations);
    gn.taylor = false;
    budget = std::make_unique<ErrorBudget>(fields, truth->rest_positions(), rom.samples(), rep.mu,
                                           gn, rom.latent());
  }

  std::unique_ptr<RunWriter> writer;
  Particles frame = out_points;
  std::vector<Vec3> x, v;
  std::vector<Mat3> tau, C;
  std::vector<double> latents;                 // ẑ of every written frame, row by row
  ErrorSum delta, stress_error, affine_error;  // eq. (11) over frames 1…N; τ and C vs the truth's
  rep.field_sources = rom.diagnostics().field_sources;
  auto output = [&](int f) {
    const double t1 = now_seconds();
    rom.particle_state(x, &v);
    const bool compare = truth && f > 0;
    if (compare || writer) rom.particle_fields(tau, C);
    if (compare) {
      const RunFrame truth_frame = truth->read_frame(size_t(f));
      const std::vector<Vec3>& phi = truth_frame.x;
      ErrorSum frame_delta;
      for (size_t p = 0; p < phi.size(); ++p) {
        frame_delta.add(x[p], phi[p]);
        stress_error.add(tau[p], truth_frame.tau[p]);
        affine_error.add(C[p], truth_frame.C[p]);
      }
      if (budget) budget->add_frame(phi, truth_frame.v, truth_frame.tau, truth_frame.C);
      rep.delta_per_frame.push_back(frame_delta.relative());
      delta.add(frame_delta);
      rep.delta = delta.relative();
      // < 0 for "not measured": a truth without stress (a rigid drop) has no relative error.
      rep.stress_error = stress_error.ref > 0 ? stress_error.relative() : -1.0;
      rep.affine_error = affine_error.ref > 0 ? affine_error.relative() : -1.0;
    }
    if (writer) {
      if (o.upsample > 1) rom.state(boost, x, &v);
      frame.x = x;
      frame.v = v;
      // Upsampled points carry their particle's τ and C (point i comes from particle i / k).
      for (size_t i = 0; i < frame.size(); ++i)
        frame.tau[i] = tau[i / size_t(o.upsample)], frame.C[i] = C[i / size_t(o.upsample)];
      writer->write_frame(frame, rom.time());
      latents.insert(latents.end(), rom.latent().data(), rom.latent().data() + rom.latent().size());
    }
    if (f > 0) {
      const double cells = rom.diagnostics().last_residual / settings.dx;
      rep.residual_cells_max = std::max(rep.residual_cells_max, cells);
      rep.residual_cells_mean += cells / settings.frames;
    }
    if (const double d = rom.diagnostics().training_distance; d >= 0 && f > 0) {
      rep.training_distance_max = std::max(rep.training_distance_max, d);
      rep.training_distance_mean += d / settings.frames;
    }
    rep.rom_output_seconds += now_seconds() - t1;
  };
  if (!o.out_path.empty()) {
    writer = std::make_unique<RunWriter>(o.out_path, out_points, settings, rep.scene, js.dump(),
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
  }
  output(0);
  Progress progress("reduced order", settings.frames, "frames");
  for (int f = 1; f <= settings.frames; ++f) {
    t0 = now_seconds();
    rom.advance_frame();
    rep.rom_seconds += now_seconds() - t0;
    output(f);
    if (!o.quiet) {
      char extra[96];
      std::snprintf(extra, sizeof extra, "|N| %zu, delta %.2f%%",
                    rom.integration_particles().size(), rep.delta >= 0 ? 100 * rep.delta : 0.0);
      progress.update(f, extra);
    }
  }
  if (!o.quiet) progress.finish();
  if (writer) {
    const size_t r = size_t(rom.latent().size());
    writer->write_table("/rom/latent", latents.size() / r, r, latents.data());
    writer->finish();
  }
  rep.rom_file = o.out_path;
  rep.rom_peak_mib = peak_rss_mib();
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
  rep.threads = threads;
  rep.cpu = cpu_model();
  rep.refreshes = d.refreshes;
  rep.rom_times = d.times;
  if (budget) rep.budget = budget->result();

  // The baselines, after the ROM so that its peak memory is its own.
  if (!baseline_inputs.runs.empty())
    measure_sweep_baselines(baseline_inputs.runs, rep.mu, *truth, settings.frames, rep.baselines);
  if (baseline_inputs.coarse) {
    measure_coarse_baseline(*baseline_inputs.coarse, baseline_inputs.coarse_json, *truth,
                            settings.frames, threads, o.quiet, rep.baselines);
    rep.baselines.coarse_scene = baseline_inputs.label;
  }
  return rep;
}

std::string latent_drift_warning(double mean_spreads, double latent_prior) {
  if (!(mean_spreads >= kLatentDriftWarning)) return "";
  char remedy[160] =
      "a weak latent prior holds it (nsf calibrate MODEL DATA chooses one on the training runs; "
      "or --latent-prior 0.0001 to 0.0003)";
  if (latent_prior > 0)
    std::snprintf(remedy, sizeof remedy, "a stronger latent prior holds it (now %g mm)",
                  1e3 * latent_prior);
  char line[512];
  std::snprintf(line, sizeof line,
                "the latent went %.1f training spreads from the training runs' latents on "
                "average: the stress field answered far from anything it was trained on, so delta "
                "may hang on its training draw; %s (docs/ROM.md, \"Latent prior\")",
                mean_spreads, remedy);
  return line;
}

std::string format_rom_report(const RomReport& r) {
  std::ostringstream s;
  char line[256];
  auto put = [&](const char* fmt, auto... args) {
    std::snprintf(line, sizeof line, fmt, args...);
    s << line << "\n";
  };
  s << "scene " << r.scene;
  if (r.has_mu) s << " at mu = " << r.mu;
  s << "\n";
  for (const auto& w : r.warnings) s << "warning: " << w << "\n";
  put("  |P| = %zu, r = %d, gamma = 3|P|/r = %.3g", r.particles, r.latent_dim, r.gamma);
  put("  |S| = %zu%s, mean |N| = %.0f (candidates %.0f, %ld full refreshes)", r.samples,
      r.samples_end != r.samples ? (" -> " + std::to_string(r.samples_end)).c_str() : "", r.mean_N,
      r.mean_K, r.refreshes);
  put("  inversion keeps %.2f%% of the samples' kinetic energy per step (energy-weighted mean)",
      100 * r.energy_kept);
  if (r.training_distance_max >= 0) {
    char prior[128] = "no latent prior";
    if (r.latent_prior > 0)
      std::snprintf(
          prior, sizeof prior, "latent prior, epsilon = %g mm from the %s", 1e3 * r.latent_prior,
          r.latent_prior_source == "model" ? "model's calibration" : r.latent_prior_source.c_str());
    put("  latent: %.2f training spreads from the training runs' latents on average, %.2f at most "
        "(%s)",
        r.training_distance_mean, r.training_distance_max, prior);
  }
  if (r.quadrature_points > 0 && r.quadrature_points < r.particles)
    put("  thinned quadrature: N drawn from %zu points standing for the %zu particles",
        r.quadrature_points, r.particles);
  s << "  " << r.field_sources << "\n";
  if (r.delta >= 0) {
    put("  delta (eq. 11) vs %s: %.3f%%", r.truth_file.c_str(), 100 * r.delta);
    // At the ROM's own state, not the truth's: what `nsf eval` gives on the truth's frames bounds
    // these from below.
    auto percent = [](double e) {
      char b[32];
      std::snprintf(b, sizeof b, "%.1f%%", 100 * e);
      return e >= 0 ? std::string(b) : std::string("n/a");
    };
    put("  stress error %s, affine error %s (relative, all particles and frames, vs the same file)",
        percent(r.stress_error).c_str(), percent(r.affine_error).c_str());
    if (r.budget) {
      auto row = [&](const char* what, const FieldErrors& e) {
        char d[32];
        std::snprintf(d, sizeof d, "%.3f%%", 100 * e.delta);
        put("    %-36s %7s %9s %9s", what, e.delta >= 0 ? d : "n/a", percent(e.stress).c_str(),
            percent(e.affine).c_str());
      };
      s << "  error budget (docs/ROM.md):             delta    stress    affine\n";
      row("representation (truth encoded)", r.budget->encoded);
      row("projection (truth's samples fitted)", r.budget->projected);
      row("reduced-order run", FieldErrors{r.delta, r.stress_error, r.affine_error});
      put("    (projection: %.1f Gauss-Newton iterations per frame on average)",
          r.budget->projection_iterations);
    }
  }
  const double steps = double(r.frames) * r.rom_steps_per_frame;
  put("  reduced order: %.3f s for %d frames (%.2f ms/frame, %d steps/frame of %.3g x dt, the "
      "step from the %s)",
      r.rom_seconds, r.frames, 1e3 * r.rom_seconds / r.frames, r.rom_steps_per_frame,
      double(r.fom_steps_per_frame) / r.rom_steps_per_frame,
      r.dt_ratio_source == "model" ? "model's calibration" : r.dt_ratio_source.c_str());
  const RomTimes& t = r.rom_times;
  put("    inference %.3f s, MPM on N %.3f s, inversion %.3f s, candidate refresh %.3f s",
      t.inference.seconds(), t.mpm.seconds(), t.inversion.seconds(), t.refresh.seconds());
  put("    per step: %.2f ms; setup %.2f s; output and delta %.2f s (not in the step time)",
      1e3 * r.rom_seconds / std::max(1.0, steps), r.rom_setup_seconds, r.rom_output_seconds);
  if (r.fom_seconds >= 0) {
    put("  full order:    %.3f s for %d frames (%.2f ms/frame, %d steps/frame)", r.fom_seconds,
        r.frames, 1e3 * r.fom_seconds / r.frames, r.fom_steps_per_frame);
    put("  speed-up (full order / reduced order, same process, same threads): %.2fx", r.speedup());
    if (!r.cpu.empty()) put("    on %d threads of %s", r.threads, r.cpu.c_str());
    put("  peak memory: reduced order %.0f MiB, full order %.0f MiB (process baseline %.0f MiB "
        "with the model loaded)%s",
        r.rom_peak_mib, r.fom_peak_mib, r.baseline_mib,
        r.peak_reset ? "" : " [peak could not be reset between phases]");
  } else {
    put("  peak memory: reduced order %.0f MiB (baseline %.0f MiB)", r.rom_peak_mib,
        r.baseline_mib);
  }
  const Baselines& b = r.baselines;
  if (b.lookup_delta >= 0 || b.coarse_delta >= 0)
    s << "  baselines (delta against the same truth; docs/RESULTS.md):\n";
  if (b.lookup_delta >= 0) {
    put("    look-up, the training run at mu = %g played back: %.3f%%", b.lookup_mu,
        100 * b.lookup_delta);
    put("    interpolation in mu of the training runs at %g and %g%s: %.3f%%", b.interp_mu_lo,
        b.interp_mu_hi, b.interp_extrapolated ? " (extrapolated)" : "", 100 * b.interp_delta);
  }
  if (b.coarse_delta >= 0) {
    char speed[64] = "";
    if (r.coarse_speedup() > 0)
      std::snprintf(speed, sizeof speed, ", speed-up %.2fx against full order", r.coarse_speedup());
    put("    coarse engine, %s (%zu particles): %.3f%% in %.3f s%s", b.coarse_scene.c_str(),
        b.coarse_particles, 100 * b.coarse_delta, b.coarse_seconds, speed);
  }
  if (!r.rom_file.empty()) s << "  wrote " << r.rom_file << "\n";
  return s.str();
}

}  // namespace nsf
