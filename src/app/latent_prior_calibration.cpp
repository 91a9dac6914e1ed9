#include "app/latent_prior_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>

#include "app/rom_run.h"
#include "app/scene_file.h"
#include "core/error.h"
#include "core/progress.h"
#include "core/timer.h"
#include "nn/dataset.h"
#include "nn/model.h"
#include "nn/neural_fields.h"

namespace nsf {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

nlohmann::json read_manifest(const std::string& data_dir) {
  const std::filesystem::path p = std::filesystem::path(data_dir) / "manifest.json";
  std::ifstream in(p);
  if (!in) return nlohmann::json::object();
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
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

std::string millimetres(double eps) {
  if (eps <= 0) return "none";
  char b[32];
  std::snprintf(b, sizeof b, "%g mm", 1e3 * eps);
  return b;
}

}  // namespace

std::optional<double> scene_latent_prior(const std::string& scene_path) {
  return app::read_scene_file(scene_path).sections.rom.latent_prior;
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
  const Dataset data(o.data_dir);
  if (!data.has_mu()) fail("calibrate: dataset ", o.data_dir, " has no parameter mu per run");
  const std::string scene = o.scene_path.empty() ? dataset_scene_file(o.data_dir) : o.scene_path;
  if (scene.empty())
    fail("calibrate: dataset ", o.data_dir,
         " names no scene file that exists here (its manifest's scene_file); give --scene");
  const std::vector<std::string> overrides = manifest_overrides(read_manifest(o.data_dir));

  CalibrationResult r;
  r.grid = o.grid;
  const std::vector<SimulationFile> runs = spread_runs(data.train(), o.runs);
  for (const SimulationFile& f : runs) {
    r.runs.push_back(std::filesystem::path(f.path).filename().string());
    r.mu.push_back(f.mu);
  }
  const double start = now_seconds();
  Progress bar("calibrating the latent prior", long(r.grid.size() * runs.size()), "runs");
  long done = 0;
  const double n = double(runs.size());
  double best_mean = kInf;  // the lowest mean of an ε measured on every run so far
  for (double eps : r.grid) {
    std::vector<double> row(runs.size(), NAN);
    double sum = 0;
    bool stopped = false;
    for (size_t k = 0; k < runs.size(); ++k) {
      RomRunOptions ro;
      ro.model_path = o.model_path;
      ro.scene_path = scene;
      ro.overrides = overrides;
      ro.mu = runs[k].mu;
      ro.latent_prior = eps;
      ro.truth_path = runs[k].path;
      ro.full_order = false;
      ro.threads = o.threads;
      ro.quiet = true;
      try {
        const RomReport rep = run_rom(ro);
        row[k] = std::isfinite(rep.delta) ? rep.delta : kInf;
      } catch (const Error& e) {
        if (std::string(e.what()).find("diverged") == std::string::npos) throw;
        row[k] = kInf;
      }
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
  j["runs"] = runs;
  j["mu"] = mu;
  j["seconds"] = seconds;
  j["grid"] = nlohmann::json::array();
  for (size_t g = 0; g < grid.size(); ++g) {
    nlohmann::json row = {
        {"latent_prior", grid[g]}, {"mean_delta", number(mean[g])}, {"stopped", stopped[g]}};
    row["delta"] = nlohmann::json::array();
    for (double d : delta[g]) row["delta"].push_back(number(d));
    j["grid"].push_back(row);
  }
  return j;
}

std::string CalibrationResult::table() const {
  std::ostringstream s;
  s << "latent prior calibration: delta on training runs";
  for (size_t k = 0; k < runs.size(); ++k)
    s << (k ? ", " : " ") << runs[k] << " (mu " << mu[k] << ")";
  s << "\n";
  char line[64];
  for (size_t g = 0; g < grid.size(); ++g) {
    std::snprintf(line, sizeof line, "  epsilon %-8s", millimetres(grid[g]).c_str());
    s << line;
    for (double d : delta[g]) {
      if (std::isnan(d))
        std::snprintf(line, sizeof line, " %9s", "-");
      else if (std::isinf(d))
        std::snprintf(line, sizeof line, " %9s", "diverged");
      else
        std::snprintf(line, sizeof line, " %8.3f%%", 100 * d);
      s << line;
    }
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
  if (NeuralFields::load(model_path).decoder() != "basis")
    return skip("an MLP model: nsf calibrate " + model_path + " " + data_dir + " does it");
  CalibrationOptions o;
  o.model_path = model_path;
  o.data_dir = data_dir;
  o.scene_path = dataset_scene_file(data_dir);
  if (o.scene_path.empty())
    return skip("the dataset's scene file is not here: nsf calibrate MODEL DATA --scene FILE");
  o.threads = threads;
  o.quiet = quiet;
  CalibrationResult r;
  try {  // the model is written and whole: a ROM that cannot run here does not undo the training
    if (const std::optional<double> set = scene_latent_prior(o.scene_path))
      return skip("scene " + o.scene_path + " sets rom.latent_prior = " + millimetres(*set));
    const Dataset data(data_dir, /*allow_incomplete=*/true);
    if (!data.incomplete().empty()) return skip("the dataset is incomplete");
    if (!data.has_mu()) return skip("the dataset has no mu");
    r = calibrate_latent_prior(o);
  } catch (const Error& e) {
    return skip(std::string("it failed: ") + e.what());
  }
  if (!quiet) std::printf("%s", r.table().c_str());
  store_calibration(model_path, r);
  std::printf("%s", r.summary().c_str());
  std::printf("  stored in %s\n", model_path.c_str());
  return true;
}

std::string CalibrationResult::summary() const {
  char line[256];
  const double best = *std::min_element(mean.begin(), mean.end());
  if (all_diverged)
    std::snprintf(line, sizeof line,
                  "latent prior: none (every epsilon diverged on some of %zu training runs; %.0f "
                  "s)\n",
                  runs.size(), seconds);
  else
    std::snprintf(line, sizeof line,
                  "latent prior: %g mm, mean delta %.3f %% on %zu training runs (%.0f s)\n",
                  1e3 * chosen, 100 * best, runs.size(), seconds);
  return line;
}

void store_calibration(const std::string& model_path, const CalibrationResult& r) {
  NeuralFields f = NeuralFields::load(model_path);
  f.model().latent_prior = r.chosen;
  f.model().latent_prior_calibration = r.to_json().dump();
  f.model().save(model_path);
}

}  // namespace nsf
