#include "rom/eval/rom_report.h"

#include <cstdio>
#include <sstream>

namespace nsf {

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
  if (r.grid_factor > 1)
    put("  ROM grid: %g times the scene's dx (its MPM step, transfers and CFL bound)",
        r.grid_factor);
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
    if (b.interp_runs > 2) {  // over the box of μ and the sweep's axes
      put("    look-up, the training run nearest in the box (mu = %g, %.3g ranges away) played "
          "back: %.3f%%",
          b.lookup_mu, b.lookup_distance, 100 * b.lookup_delta);
      put("    interpolation of the %d training runs nearest in the box (inverse squared "
          "distance): %.3f%%",
          b.interp_runs, 100 * b.interp_delta);
    } else {
      put("    look-up, the training run at mu = %g played back: %.3f%%", b.lookup_mu,
          100 * b.lookup_delta);
      put("    interpolation in mu of the training runs at %g and %g%s: %.3f%%", b.interp_mu_lo,
          b.interp_mu_hi, b.interp_extrapolated ? " (extrapolated)" : "", 100 * b.interp_delta);
    }
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
