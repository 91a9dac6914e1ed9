#include "rom/calibration/latent_prior_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <set>
#include <sstream>

#include "core/error.h"
#include "core/exclusive_file.h"
#include "core/input_file.h"
#include "core/progress.h"
#include "core/timer.h"
#include "data/sweep_spec.h"
#include "io/run_reader.h"
#include "nn/dataset.h"
#include "nn/neural_fields.h"
#include "rom/calibration/rom_calibration.h"
#include "rom/eval/generalize.h"
#include "rom/eval/rom_evaluation.h"
#include "rom/setup/scene_file.h"
#include "rom/step/rom_diverged.h"

namespace nsf {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

nlohmann::json read_manifest(const std::string& data_dir) {
  const std::filesystem::path p = std::filesystem::path(data_dir) / "manifest.json";
  std::error_code ec;
  if (!std::filesystem::exists(p, ec)) return nlohmann::json::object();
  const nlohmann::json j =
      nlohmann::json::parse(read_input_file(p.string(), "dataset manifest"), nullptr, false);
  return j.is_object() ? j : nlohmann::json::object();
}

// The sweep's own --set overrides, which the training runs were simulated with.
std::vector<std::string> manifest_overrides(const nlohmann::json& m) {
  std::vector<std::string> out;
  if (m.contains("overrides") && m["overrides"].is_array())
    for (const auto& o : m["overrides"])
      if (o.is_string()) out.push_back(o.get<std::string>());
  return out;
}

// The scene values a calibration's ROM runs take: the sweep's own, then its --set.
std::vector<std::string> calibration_overrides(const CalibrationOptions& o) {
  std::vector<std::string> overrides = manifest_overrides(read_manifest(o.data_dir));
  overrides.insert(overrides.end(), o.overrides.begin(), o.overrides.end());
  return overrides;
}

// `count` runs spread over the sweep (ordered by μ): the middle run of each of `count` equal
// shares, so that the ends, where the prior's surface has one side only, do not decide alone.
std::vector<SimulationFile> spread_runs(std::vector<SimulationFile> runs, int count) {
  std::stable_sort(runs.begin(), runs.end(),
                   [](const SimulationFile& a, const SimulationFile& b) { return a.mu < b.mu; });
  std::vector<SimulationFile> out;
  const size_t n = runs.size();
  for (int i = 0; i < count && size_t(i) < n; ++i) {
    const size_t k = (size_t(2 * i + 1) * n) / size_t(2 * std::min<size_t>(size_t(count), n));
    if (out.empty() || out.back().path != runs[k].path) out.push_back(runs[k]);
  }
  return out;
}

// One case the ROM is measured on: a training run, whose file is the truth, or a perturbed draw
// (CalibrationOptions::unseen), whose truth is run at full order the first time it is measured
// and kept for the others.
struct Case {
  std::string label;                   // the run's file name, or the draw's perturbation and v
  std::optional<double> mu;            // none for a draw of a scene without a sweep
  std::vector<std::string> overrides;  // the run's own sections, or the draw's axes and templates
  std::string truth;                   // the truth's file; "" until the draw's is made
  std::string truth_out;               // where a draw's full-order run goes
};

// One ROM run against one case. δ is +inf where the latent dynamics diverged or the ROM
// refused the step (the tracked state's CFL bound); any other failure is thrown.
struct Measured {
  double delta = 0;
  double rom_seconds = 0;
  int frames = 0, steps_per_frame = 0;
};

// A run of a sweep with "vary" axes or collider paths holds more than μ: the sections those set
// ("colliders" for a path, the first key of each axis's templates), taken from the scene stored
// in the run file, so that the ROM runs the case the run is. Nothing for a sweep over μ alone.
std::vector<std::string> own_sections(const std::string& scene,
                                      const std::vector<std::string>& overrides,
                                      const SimulationFile& run) {
  const SceneFile f = read_scene_file(scene, overrides);
  if (!f.sections.sweep) return {};
  const SweepSpec& spec = *f.sections.sweep;
  std::set<std::string> keys;
  if (!spec.paths.empty()) keys.insert("colliders");
  for (const ParameterAxis& axis : spec.vary)
    for (const std::string& t : axis.set) keys.insert(t.substr(0, t.find_first_of(".[=")));
  if (keys.empty()) return {};
  const nlohmann::json stored = nlohmann::json::parse(RunReader(run.path).scene_json());
  std::vector<std::string> out;
  for (const std::string& key : keys)
    if (stored.contains(key)) out.push_back(key + "=" + stored.at(key).dump());
  return out;
}

Measured measure(const CalibrationOptions& o, const std::string& scene,
                 const std::vector<std::string>& overrides, Case& c, double eps,
                 std::optional<double> dt_ratio) {
  RomEvalOptions ro;
  ro.model_path = o.model_path;
  ro.scene_path = scene;
  ro.overrides = overrides;
  ro.overrides.insert(ro.overrides.end(), c.overrides.begin(), c.overrides.end());
  ro.mu = c.mu;
  ro.latent_prior = eps;
  ro.dt_ratio = dt_ratio;
  ro.truth_path = c.truth;
  ro.full_order = c.truth.empty();
  ro.fom_out = c.truth.empty() ? c.truth_out : "";
  if (o.unseen) ro.profile = "unseen";
  ro.threads = o.threads;
  ro.quiet = true;
  // Every perturbed case lies outside the family, as its table says: not said once per run.
  ro.print_warnings = !o.unseen;
  Measured m;
  try {
    const RomReport rep = evaluate_rom(ro);
    m.delta = std::isfinite(rep.delta) ? rep.delta : kInf;
    m.rom_seconds = rep.rom_seconds;
    m.frames = rep.frames;
    m.steps_per_frame = rep.rom_steps_per_frame;
  } catch (const RomDiverged&) {
    m.delta = kInf;
  }
  // A draw's truth, made before the ROM ran, serves its other runs (any other failure ends the
  // calibration).
  if (c.truth.empty()) c.truth = c.truth_out;
  return m;
}

}  // namespace

size_t best_step(const StepCalibration& s) {
  size_t best = 0;
  for (size_t i = 1; i < s.mean.size(); ++i)
    if (!s.stopped[i] && s.mean[i] < s.mean[best]) best = i;
  return best;
}

double step_limit(const StepCalibration& s) {
  return std::max(s.tolerance * s.mean[best_step(s)], s.budget);
}

double chosen_step(const StepCalibration& s) {
  if (s.mean.empty() || std::isinf(s.mean[0])) return -1;
  const double limit = step_limit(s);
  double chosen = -1;
  for (size_t i = 0; i < s.mean.size(); ++i)
    if (!s.stopped[i] && s.mean[i] <= limit) chosen = s.ratios[i];
  return chosen;
}

namespace {

// The step pass: each ratio at ε on the same runs; the largest within tolerance of the best wins.
StepCalibration calibrate_step(const CalibrationOptions& o, const std::string& scene,
                               const std::vector<std::string>& overrides, std::vector<Case>& runs,
                               double eps) {
  StepCalibration s;
  s.ratios = o.dt_ratios;
  s.tolerance = o.dt_tolerance;
  s.budget = o.dt_budget;
  Progress bar("calibrating the ROM step", long(s.ratios.size() * runs.size()), "runs");
  long done = 0;
  const double n = double(runs.size());
  for (size_t i = 0; i < s.ratios.size(); ++i) {
    std::vector<double> row(runs.size(), NAN);
    double sum = 0, seconds = 0;
    int frames = 0, per_frame = 0;
    bool stopped = false;
    for (size_t k = 0; k < runs.size(); ++k) {
      const Measured m = measure(o, scene, overrides, runs[k], eps, s.ratios[i]);
      row[k] = m.delta;
      sum += m.delta;
      seconds += m.rom_seconds;
      frames += m.frames;
      if (m.steps_per_frame) per_frame = m.steps_per_frame;
      if (!o.quiet) {
        char what[48];
        std::snprintf(what, sizeof what, "dt ratio %g", s.ratios[i]);
        bar.update(++done, what);
      }
      // Out: failed, or its runs so far already put the mean over the tolerance.
      stopped = i > 0 && !std::isinf(m.delta) && k + 1 < runs.size() && sum / n > s.limit;
      if (std::isinf(m.delta) || stopped) {
        done += long(runs.size() - k - 1);
        break;
      }
    }
    s.delta.push_back(row);
    s.mean.push_back(std::isinf(sum) ? kInf : sum / n);
    s.stopped.push_back(stopped);
    s.steps_per_frame.push_back(per_frame);
    s.rom_ms_per_frame.push_back(frames ? 1e3 * seconds / frames : NAN);
    if (i == 0 && std::isinf(s.mean[0])) break;  // nothing to hold the others to
    s.limit = step_limit(s);  // only falls, so a ratio stopped at it is over the final one too
  }
  if (!o.quiet) bar.finish();
  s.chosen = chosen_step(s);
  return s;
}

// The training runs measured on: `o.runs` of them spread over the sweep.
std::vector<Case> training_cases(const CalibrationOptions& o, const std::string& scene,
                                 const std::vector<std::string>& overrides) {
  const Dataset data(o.data_dir);
  if (!data.has_mu()) fail("calibrate: dataset ", o.data_dir, " has no parameter mu per run");
  std::vector<Case> cases;
  for (const SimulationFile& f : spread_runs(data.train(), o.runs)) {
    Case c;
    c.label = std::filesystem::path(f.path).filename().string();
    c.mu = f.mu;
    c.overrides = own_sections(scene, overrides, f);
    c.truth = f.path;
    cases.push_back(std::move(c));
  }
  return cases;
}

// The perturbed cases measured on: `o.draws` draws of the scene's "generalize" section from its
// calibration seed (or `o.seed`), which must not be the benchmark's; `seed` is set to it.
std::vector<Case> unseen_cases(const CalibrationOptions& o, const std::string& scene,
                               const std::vector<std::string>& overrides, const PrivateDir& dir,
                               uint64_t& seed) {
  const SceneFile file = read_scene_file(scene, overrides);
  if (!file.sections.generalize)
    fail("calibrate --unseen: scene ", scene,
         " has no \"generalize\" section to draw perturbed cases from (docs/GENERALIZE.md)");
  if (!file.sections.rom.unseen)
    fail("calibrate --unseen: scene ", scene,
         " has no rom.unseen profile to calibrate (docs/GENERALIZE.md, \"Outside the training "
         "family\")");
  const GeneralizeSpec& spec = *file.sections.generalize;
  seed = o.seed ? *o.seed : spec.calibration_seed;
  if (seed == spec.seed)
    fail("calibrate --unseen: seed ", seed,
         " is the benchmark's (the scene's generalize.seed): a model calibrated on the draws "
         "that score it would be scored on what it saw; give another --seed");
  const SweepSpec* sweep = file.sections.sweep ? &*file.sections.sweep : nullptr;
  std::vector<Case> cases;
  for (const PerturbationDraw& d : plan_draws(spec, sweep, o.draws, seed)) {
    RomEvalOptions ro;
    set_up_draw(ro, d, sweep);
    Case c;
    char label[160];
    std::snprintf(label, sizeof label, "draw %d (%s, v = %.4g)", d.index, d.perturbation.c_str(),
                  d.value);
    c.label = label;
    c.mu = ro.mu;
    c.overrides = std::move(ro.overrides);
    c.truth_out = dir.path("draw_" + std::to_string(d.index) + ".h5");
    cases.push_back(std::move(c));
  }
  return cases;
}

// One table row's δ per run: "-" where skipped, `failed` where +inf.
std::string delta_cells(const std::vector<double>& row, const char* failed) {
  std::string out;
  char cell[32];
  for (double d : row) {
    if (std::isnan(d))
      std::snprintf(cell, sizeof cell, " %9s", "-");
    else if (std::isinf(d))
      std::snprintf(cell, sizeof cell, " %9s", failed);
    else
      std::snprintf(cell, sizeof cell, " %8.3f%%", 100 * d);
    out += cell;
  }
  return out;
}

std::string millimetres(double eps) {
  if (eps <= 0) return "none";
  char b[32];
  std::snprintf(b, sizeof b, "%g mm", 1e3 * eps);
  return b;
}

}  // namespace

size_t calibration_recipes(const std::string& scene_path) {
  if (scene_path.empty()) return 0;
  return read_scene_file(scene_path).sections.calibrate.size();
}

void apply_calibration_recipe(CalibrationOptions& o, const CalibrationGiven& given, size_t index) {
  const std::string scene = o.scene_path.empty() ? dataset_scene_file(o.data_dir) : o.scene_path;
  if (scene.empty()) return;
  const std::vector<CalibrationRecipe> recipes = read_scene_file(scene).sections.calibrate;
  if (recipes.empty()) return;
  if (index >= recipes.size())
    fail("calibrate: scene ", scene, " gives ", recipes.size(),
         " calibration recipes (train.calibrate); there is no recipe ", index + 1);
  const CalibrationRecipe& c = recipes[index];
  std::ostringstream took;
  const auto list = [&](const char* name, const auto& v) {
    took << " " << name;
    for (size_t i = 0; i < v.size(); ++i) took << (i ? "," : " ") << v[i];
  };
  if (!c.grid.empty() && !given.grid) o.grid = c.grid, list("grid", c.grid);
  if (!c.dt_ratios.empty() && !given.dt_ratios)
    o.dt_ratios = c.dt_ratios, list("dt_ratios", c.dt_ratios);
  if (c.unseen && !given.unseen) o.unseen = true, took << " unseen";
  if (c.draws > 0 && !given.draws) o.draws = c.draws, took << " draws " << c.draws;
  if (!c.set.empty() && !given.set) {
    o.overrides.insert(o.overrides.end(), c.set.begin(), c.set.end());
    list("set", c.set);
  }
  if (!o.quiet && !took.str().empty()) {
    const size_t n = recipes.size();
    const std::string which =
        n > 1 ? " " + std::to_string(index + 1) + " of " + std::to_string(n) : std::string();
    std::printf("calibration recipe%s of %s:%s\n", which.c_str(), scene.c_str(),
                took.str().c_str());
  }
}

SceneRomSettings scene_rom_settings(const CalibrationOptions& o, DecoderFamily family) {
  const std::string scene = o.scene_path.empty() ? dataset_scene_file(o.data_dir) : o.scene_path;
  if (scene.empty()) return {};
  const SceneFile file = read_scene_file(scene, calibration_overrides(o));
  const RomSection& rom = file.sections.rom;
  if (o.unseen) {
    if (!rom.unseen) return {};  // calibrate_latent_prior says so
    const RomSection& u = *rom.unseen;
    return {u.tracks_stress(family), u.latent_prior, u.dt_ratio};
  }
  const RomSection& section = rom.for_run(family);
  return {rom.tracks_stress(family), section.latent_prior, section.dt_ratio};
}

std::string dataset_scene_file(const std::string& data_dir) {
  const nlohmann::json m = read_manifest(data_dir);
  if (!m.contains("scene_file") || !m["scene_file"].is_string()) return "";
  const std::string f = m["scene_file"].get<std::string>();
  return !f.empty() && std::filesystem::is_regular_file(f) ? f : "";
}

CalibrationResult calibrate_latent_prior(const CalibrationOptions& o) {
  if (o.grid.empty()) fail("calibrate: the grid of latent prior lengths is empty");
  for (double e : o.grid)
    if (!(e >= 0) || !std::isfinite(e))
      fail("calibrate: a latent prior length must be finite and at least 0, got ", e);
  if (o.runs < 1) fail("calibrate: --runs must be at least 1, got ", o.runs);
  for (size_t i = 0; i < o.dt_ratios.size(); ++i)
    if (!(o.dt_ratios[i] > 0) || !std::isfinite(o.dt_ratios[i]) ||
        (i && !(o.dt_ratios[i] > o.dt_ratios[i - 1])))
      fail(
          "calibrate: --dt-ratios must be positive and ascending (the first is the reference), "
          "got ",
          o.dt_ratios[i], " after ", i ? o.dt_ratios[i - 1] : 0.0);
  if (!(o.dt_budget >= 0) || !std::isfinite(o.dt_budget))
    fail("calibrate: --dt-budget must be a delta of at least 0, got ", o.dt_budget);
  if (!o.dt_ratios.empty() && !(o.dt_tolerance >= 1))
    fail(
        "calibrate: --dt-tolerance must be at least 1 (a factor on the best ratio's mean delta), "
        "got ",
        o.dt_tolerance);
  if (o.unseen && o.draws < 1) fail("calibrate: --draws must be at least 1, got ", o.draws);
  const std::string scene = o.scene_path.empty() ? dataset_scene_file(o.data_dir) : o.scene_path;
  if (scene.empty())
    fail("calibrate: dataset ", o.data_dir,
         " names no scene file that exists here (its manifest's scene_file); give --scene");
  const std::vector<std::string> overrides = calibration_overrides(o);

  CalibrationResult r;
  r.grid = o.grid;
  r.unseen = o.unseen;
  r.tracked = scene_rom_settings(o, NeuralFields::load(o.model_path).family()).tracked;
  std::unique_ptr<PrivateDir> truths;  // the draws' full-order runs, gone with the calibration
  std::vector<Case> runs;
  if (o.unseen) {
    truths = std::make_unique<PrivateDir>("nsf_calibrate_unseen");
    runs = unseen_cases(o, scene, overrides, *truths, r.seed);
  } else {
    runs = training_cases(o, scene, overrides);
  }
  for (const Case& c : runs) {
    r.runs.push_back(c.label);
    r.mu.push_back(c.mu.value_or(NAN));
  }
  const double start = now_seconds();
  Progress bar(
      o.unseen ? "calibrating the unseen profile's latent prior" : "calibrating the latent prior",
      long(r.grid.size() * runs.size()), o.unseen ? "draws" : "runs");
  long done = 0;
  const double n = double(runs.size());
  double best_mean = kInf;  // the lowest mean of an ε measured on every run so far
  for (double eps : r.grid) {
    std::vector<double> row(runs.size(), NAN);
    double sum = 0;
    bool stopped = false;
    for (size_t k = 0; k < runs.size(); ++k) {
      const std::optional<double> ratio =
          o.dt_ratios.empty() ? std::nullopt : std::optional<double>(o.dt_ratios[0]);
      row[k] = measure(o, scene, overrides, runs[k], eps, ratio).delta;
      sum += row[k];
      if (!o.quiet) bar.update(++done, "epsilon " + millimetres(eps));
      // Out: diverged, or its mean can no longer be the lowest (every δ ≥ 0, so sum / n bounds
      // it from below). The choice is the one the whole grid would give, in fewer runs.
      stopped = !std::isinf(row[k]) && k + 1 < runs.size() && sum / n > best_mean;
      if (std::isinf(row[k]) || stopped) {
        done += long(runs.size() - k - 1);
        break;
      }
    }
    r.delta.push_back(row);
    r.mean.push_back(std::isinf(sum) ? kInf : sum / n);
    r.stopped.push_back(stopped);
    if (!stopped) best_mean = std::min(best_mean, r.mean.back());
  }
  if (!o.quiet) bar.finish();
  const size_t best = size_t(std::min_element(r.mean.begin(), r.mean.end()) - r.mean.begin());
  r.all_diverged = std::isinf(r.mean[best]);
  r.chosen = r.all_diverged ? 0.0 : r.grid[best];
  if (!o.dt_ratios.empty()) r.step = calibrate_step(o, scene, overrides, runs, r.chosen);
  r.seconds = now_seconds() - start;
  return r;
}

nlohmann::json CalibrationResult::to_json() const {
  auto number = [](double v) {
    return std::isnan(v)   ? nlohmann::json()
           : std::isinf(v) ? nlohmann::json("diverged")
                           : nlohmann::json(v);
  };
  nlohmann::json j;
  j["chosen"] = chosen;
  j["all_diverged"] = all_diverged;
  j["tracked"] = tracked;
  j["unseen"] = unseen;
  if (unseen) j["seed"] = seed;  // generalize refuses to score the model on these draws
  j["runs"] = runs;
  j["mu"] = nlohmann::json::array();
  for (double m : mu) j["mu"].push_back(std::isnan(m) ? nlohmann::json() : nlohmann::json(m));
  j["seconds"] = seconds;
  j["grid"] = nlohmann::json::array();
  for (size_t g = 0; g < grid.size(); ++g) {
    nlohmann::json row = {
        {"latent_prior", grid[g]}, {"mean_delta", number(mean[g])}, {"stopped", stopped[g]}};
    row["delta"] = nlohmann::json::array();
    for (double d : delta[g]) row["delta"].push_back(number(d));
    j["grid"].push_back(row);
  }
  if (step) {
    nlohmann::json s = {{"tolerance", step->tolerance},
                        {"budget", step->budget},
                        {"limit", step->limit},
                        {"chosen", step->chosen > 0 ? nlohmann::json(step->chosen) : nullptr},
                        {"ratios", nlohmann::json::array()}};
    for (size_t i = 0; i < step->mean.size(); ++i) {
      nlohmann::json row = {{"dt_ratio", step->ratios[i]},
                            {"steps_per_frame", step->steps_per_frame[i]},
                            {"mean_delta", number(step->mean[i])},
                            {"stopped", bool(step->stopped[i])},
                            {"rom_ms_per_frame", number(step->rom_ms_per_frame[i])}};
      row["delta"] = nlohmann::json::array();
      for (double d : step->delta[i]) row["delta"].push_back(number(d));
      s["ratios"].push_back(row);
    }
    j["step"] = s;
  }
  return j;
}

std::string CalibrationResult::table() const {
  std::ostringstream s;
  s << "latent prior calibration" << (unseen ? " of the unseen profile" : "")
    << (tracked ? (unseen ? " (tracked state)" : " of the tracked state") : "");
  if (unseen)
    s << ": delta on perturbed cases against their full-order runs (seed " << seed << "):";
  else
    s << ": delta on training runs";
  for (size_t k = 0; k < runs.size(); ++k) {
    s << (k ? ", " : " ") << runs[k];
    if (!std::isnan(mu[k])) s << " (mu " << mu[k] << ")";
  }
  s << "\n";
  char line[64];
  for (size_t g = 0; g < grid.size(); ++g) {
    std::snprintf(line, sizeof line, "  epsilon %-8s", millimetres(grid[g]).c_str());
    s << line;
    s << delta_cells(delta[g], "diverged");
    if (std::isinf(mean[g]))
      std::snprintf(line, sizeof line, "   mean -");
    else if (stopped[g])
      std::snprintf(line, sizeof line, "   mean > %.3f%% (cannot win)", 100 * mean[g]);
    else
      std::snprintf(line, sizeof line, "   mean %.3f%%", 100 * mean[g]);
    s << line << (grid[g] == chosen && !all_diverged ? "  <- chosen" : "") << "\n";
  }
  if (all_diverged)
    s << "  every epsilon diverged on some run: the model keeps no prior (latent prior 0); more "
         "samples or a smaller rom.dt_ratio may hold the dynamics\n";
  if (step) {
    s << "ROM step calibration at epsilon " << millimetres(chosen)
      << ": delta on the same runs; a ratio qualifies at a mean within " << step->tolerance
      << "x the best's";
    if (step->budget > 0) s << " or within " << 100 * step->budget << "%";
    s << "\n";
    for (size_t i = 0; i < step->mean.size(); ++i) {
      std::snprintf(line, sizeof line, "  dt ratio %-6g", step->ratios[i]);
      s << line;
      s << delta_cells(step->delta[i], "failed");
      if (std::isinf(step->mean[i]))
        std::snprintf(line, sizeof line, "   mean -");
      else if (step->stopped[i])
        std::snprintf(line, sizeof line, "   mean > %.3f%% (over)", 100 * step->mean[i]);
      else
        std::snprintf(line, sizeof line, "   mean %.3f%%, %d steps/frame, ROM %.1f ms/frame",
                      100 * step->mean[i], step->steps_per_frame[i], step->rom_ms_per_frame[i]);
      s << line << (step->ratios[i] == step->chosen ? "  <- chosen" : "") << "\n";
    }
    if (step->chosen < 0)
      s << "  the first ratio failed on some run: no step is chosen (nsf rom keeps the scene's)\n";
  }
  return s.str();
}

bool calibrate_trained_model(const std::string& model_path, const std::string& data_dir,
                             int threads, bool quiet) {
  const auto skip = [&](const std::string& why) {
    std::printf(
        "latent prior: not calibrated (%s); nsf rom uses the scene's rom.latent_prior, "
        "else none\n",
        why.c_str());
    return false;
  };
  if (NeuralFields::load(model_path).family() != DecoderFamily::basis)
    return skip("an MLP model: nsf calibrate " + model_path + " " + data_dir + " does it");
  CalibrationOptions o;
  o.model_path = model_path;
  o.data_dir = data_dir;
  o.scene_path = dataset_scene_file(data_dir);
  if (o.scene_path.empty())
    return skip("the dataset's scene file is not here: nsf calibrate MODEL DATA --scene FILE");
  o.threads = threads;
  o.quiet = quiet;
  try {
    const Dataset data(data_dir, /*allow_incomplete=*/true);
    if (!data.incomplete().empty()) return skip("the dataset is incomplete");
    if (!data.has_mu()) return skip("the dataset has no mu");
  } catch (const Error& e) {
    return skip(std::string("it failed: ") + e.what());
  }
  bool calibrated = false;
  const size_t recipes = std::max<size_t>(1, calibration_recipes(o.scene_path));
  for (size_t i = 0; i < recipes; ++i) {
    CalibrationOptions one = o;
    CalibrationResult r;
    try {  // the model is written and whole: a ROM that cannot run here does not undo the training
      apply_calibration_recipe(one, {}, i);
      const SceneRomSettings scene = scene_rom_settings(one, DecoderFamily::basis);
      if (scene.latent_prior) {
        skip("scene " + o.scene_path + " sets rom." + (one.unseen ? "unseen." : "") +
             "latent_prior = " + millimetres(*scene.latent_prior) +
             (scene.tracked && !one.unseen ? " for runs with the tracked state" : ""));
        continue;
      }
      r = calibrate_latent_prior(one);
    } catch (const Error& e) {
      skip(std::string("it failed: ") + e.what());
      continue;
    }
    if (!quiet) std::printf("%s", r.table().c_str());
    store_calibration(model_path, r);
    std::printf("%s", r.summary().c_str());
    std::printf("  stored in %s\n", model_path.c_str());
    calibrated = true;
  }
  return calibrated;
}

std::string CalibrationResult::summary() const {
  char line[256];
  const double best = *std::min_element(mean.begin(), mean.end());
  if (all_diverged)
    std::snprintf(line, sizeof line,
                  "latent prior: none (every epsilon diverged on some of %zu %s; %.0f s)\n",
                  runs.size(), unseen ? "perturbed cases" : "training runs", seconds);
  else
    std::snprintf(line, sizeof line, "latent prior: %g mm, mean delta %.3f %% on %zu %s (%.0f s)\n",
                  1e3 * chosen, 100 * best, runs.size(),
                  unseen ? "perturbed cases" : "training runs", seconds);
  std::string out = unseen    ? "unseen profile: " + std::string(line)
                    : tracked ? "tracked state: " + std::string(line)
                              : std::string(line);
  if (step && step->chosen > 0) {
    const size_t i = size_t(std::find(step->ratios.begin(), step->ratios.end(), step->chosen) -
                            step->ratios.begin());
    const size_t best = best_step(*step);
    std::snprintf(line, sizeof line,
                  "ROM step: %g x dt (%d steps a frame), mean delta %.3f %% against %.3f %% at "
                  "%g x dt (the best)\n",
                  step->chosen, step->steps_per_frame[i], 100 * step->mean[i],
                  100 * step->mean[best], step->ratios[best]);
    out += line;
  } else if (step) {
    out += "ROM step: not chosen (the first ratio failed on some run)\n";
  }
  return out;
}

void store_calibration(const std::string& model_path, const CalibrationResult& r) {
  RomCalibrations all = rom_calibrations(NeuralFields::load(model_path));
  RomCalibration& c = r.unseen ? all.unseen : r.tracked ? all.tracked : all.decoded;
  c.latent_prior = r.chosen;
  c.table = r.to_json();
  if (r.step) c.dt_ratio = r.step->chosen;
  NeuralFields::store_attachment(model_path, kRomCalibrationAttachment, to_json(all).dump());
}

}  // namespace nsf
