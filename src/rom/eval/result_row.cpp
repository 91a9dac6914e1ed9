#include "rom/eval/result_row.h"

namespace nsf {

namespace {

// The keys of a row that are the machine's, not the method's: timings, memory, speed-ups.
bool machine_key(const std::string& k) {
  const auto ends = [&](const std::string& tail) {
    return k.size() >= tail.size() && k.compare(k.size() - tail.size(), tail.size(), tail) == 0;
  };
  return ends("_seconds") || ends("_mib") || k == "speedup" || k == "coarse_speedup" ||
         k == "threads" || k == "cpu" || k == "picture";
}

// Where a setting came from, not a figure: the setting itself is compared. `--check` hands the
// rerun the stored row's prior and step on its command line, so the source differs by
// construction. Nor is the model file's checksum a figure: a recalibration rewrites the file and
// leaves the decoders as they were (`--check` names a changed file beside its verdict).
bool provenance_key(const std::string& k) {
  return k == "latent_prior_source" || k == "dt_ratio_source" || k == "model_crc32";
}

// What the run was: μ, the sizes and the ROM's setup.
void add_setup(const RomReport& r, nlohmann::json& j) {
  j["mu"] = r.mu;
  j["particles"] = r.particles;
  j["r"] = r.latent_dim;
  j["gamma"] = r.gamma;
  j["samples"] = r.samples;
  j["samples_end"] = r.samples_end;
  j["mean_N"] = r.mean_N;
  j["quadrature_points"] = r.quadrature_points;
  j["quadrature_per_cell"] = r.quadrature_per_cell;
  j["rom_grid"] = r.grid_factor;
  j["threads"] = r.threads;
  if (!r.cpu.empty()) j["cpu"] = r.cpu;
  j["latent_prior"] = r.latent_prior;
  if (r.sample_condition >= 0) {  // QDEIM's samples (rom.sampling = qdeim)
    j["sampling"] = r.sampling;
    j["sample_condition"] = r.sample_condition;
  }
  j["latent_prior_source"] = r.latent_prior_source;
  // Only a run outside the training family says so: the in-sweep rows stay as they were.
  if (!r.outside_family.empty()) j["outside_family"] = r.outside_family;
  if (r.profile != "family") j["profile"] = r.profile;
}

// What it measured against full order: δ and the field errors, with the budget's encoded and
// projected bounds beside them.
void add_errors(const RomReport& r, nlohmann::json& j) {
  j["delta"] = r.delta;
  j["stress_error"] = r.stress_error;
  j["affine_error"] = r.affine_error;
  j["frames"] = r.frames;
  if (!r.delta_per_frame.empty()) j["delta_per_frame"] = r.delta_per_frame;  // frames 1…N
  j["energy_kept"] = r.energy_kept;
  if (r.budget) {
    j["delta_encoded"] = r.budget->encoded.delta;
    j["stress_error_encoded"] = r.budget->encoded.stress;
    j["affine_error_encoded"] = r.budget->encoded.affine;
    j["delta_projected"] = r.budget->projected.delta;
    j["stress_error_projected"] = r.budget->projected.stress;
    j["affine_error_projected"] = r.budget->projected.affine;
  }
}

// What it cost: time, memory and steps, for both engines (and the model's training time).
void add_costs(const RomReport& r, nlohmann::json& j) {
  j["rom_seconds"] = r.rom_seconds;
  j["fom_seconds"] = r.fom_seconds;
  j["speedup"] = r.speedup();
  j["inference_seconds"] = r.rom_times.inference.seconds();
  j["mpm_seconds"] = r.rom_times.mpm.seconds();
  j["inversion_seconds"] = r.rom_times.inversion.seconds();
  j["refresh_seconds"] = r.rom_times.refresh.seconds();
  j["rom_peak_mib"] = r.rom_peak_mib;
  j["fom_peak_mib"] = r.fom_peak_mib;
  j["baseline_mib"] = r.baseline_mib;
  j["rom_steps_per_frame"] = r.rom_steps_per_frame;
  j["dt_ratio"] = r.dt_ratio;
  j["dt_ratio_source"] = r.dt_ratio_source;
  j["fom_steps_per_frame"] = r.fom_steps_per_frame;
  j["field_sources"] = r.field_sources;
  if (r.train_seconds > 0) j["train_seconds"] = r.train_seconds;
}

// The baselines (rom/eval/baselines.h), where measured.
void add_baselines(const RomReport& r, nlohmann::json& j) {
  const Baselines& b = r.baselines;
  if (b.lookup_delta >= 0) {
    j["lookup_delta"] = b.lookup_delta;
    j["lookup_mu"] = b.lookup_mu;
    j["interp_delta"] = b.interp_delta;
    j["interp_mu"] = {b.interp_mu_lo, b.interp_mu_hi};
    j["interp_extrapolated"] = b.interp_extrapolated;
    if (b.interp_runs > 2) j["interp_runs"] = b.interp_runs;
  }
  if (b.coarse_delta >= 0) {
    j["coarse_delta"] = b.coarse_delta;
    j["coarse_seconds"] = b.coarse_seconds;
    j["coarse_speedup"] = r.coarse_speedup();
    j["coarse_particles"] = b.coarse_particles;
    j["coarse_scene"] = b.coarse_scene;
  }
}

}  // namespace

std::vector<std::string> row_differences(const nlohmann::json& stored,
                                         const nlohmann::json& fresh) {
  // Keys only the rerun has were recorded after the row was made (model_crc32, say).
  std::vector<std::string> out;
  for (auto it = stored.begin(); it != stored.end(); ++it) {
    const std::string& k = it.key();
    if (machine_key(k) || provenance_key(k)) continue;
    if (!fresh.contains(k))
      out.push_back(k + ": stored " + it->dump() + ", not in the rerun");
    else if (*it != fresh.at(k))
      out.push_back(k + ": stored " + it->dump() + ", now " + fresh.at(k).dump());
  }
  return out;
}

nlohmann::json result_json(const RomReport& r, const std::string& scene_file,
                           const std::string& model_file, const std::string& picture,
                           const std::string& label) {
  nlohmann::json j;
  j["scene"] = r.scene;
  j["label"] = label;
  j["scene_file"] = scene_file;
  j["model_file"] = model_file;
  if (!r.model_checksum.empty()) j["model_crc32"] = r.model_checksum;
  j["picture"] = picture;
  add_setup(r, j);
  add_errors(r, j);
  add_costs(r, j);
  add_baselines(r, j);
  j["rom_setup_seconds"] = r.rom_setup_seconds;
  j["warnings"] = r.warnings;
  j["guarded"] = r.guarded;
  j["recoveries"] = r.recoveries;
  return j;
}

}  // namespace nsf
