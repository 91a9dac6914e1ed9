#include "rom/eval/baseline_inputs.h"

#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "data/sweep_spec.h"
#include "nn/dataset.h"

namespace nsf {

namespace {

// The coarse engine's scene at μ, built once so that a scene it cannot build fails now.
void read_coarse_scene(const RomEvalOptions& o, const RomSetup& setup, BaselineInputs& in) {
  const std::string path = o.coarse_scene.empty() ? o.scene_path : o.coarse_scene;
  std::vector<std::string> overrides = o.overrides;  // the same case on the coarse scene
  if (o.coarse_factor > 0) {
    const std::vector<std::string> coarser =
        coarser_overrides(read_scene_file(path, overrides).json, o.coarse_factor);
    overrides.insert(overrides.end(), coarser.begin(), coarser.end());
  }
  in.coarse = read_scene_file(path, overrides);
  in.coarse_json = in.coarse->json;
  in.label = in.coarse_json.value("name", path);
  if (o.coarse_factor > 0) {
    char at[48];
    std::snprintf(at, sizeof at, " at %gx dx", o.coarse_factor);
    in.label += at;
  }
  if (setup.has_mu) {
    if (!in.coarse->sections.sweep)
      fail("rom: the coarse scene ", path, " has no \"sweep\" section to set mu");
    apply_overrides(in.coarse_json, sweep_overrides(*in.coarse->sections.sweep, setup.mu));
  }
  build_scene_file(*in.coarse, in.coarse_json);  // fails now on a scene it cannot build
}

std::vector<TrainingRun> read_training_runs(const RomEvalOptions& o, const RomSetup& setup) {
  const Dataset data(o.baseline_data);
  if (!setup.has_mu || !data.has_mu())
    fail("rom: look-up and interpolation (--baselines ", o.baseline_data,
         ") need runs at other values of the scene's swept parameter mu");
  if (data.rest_positions() != setup.scene.particles.X)
    fail("rom: dataset ", o.baseline_data, " is not scene ", o.scene_path,
         " (other particles): its runs cannot stand in for this one");
  std::vector<TrainingRun> runs;
  for (const SimulationFile& s : data.train()) {
    TrainingRun run{s.path, s.mu, {}};
    for (const ParameterRange& p : s.box.parameters)
      if (p.name != setup.sweep_parameter) run.axes[p.name] = p.lo;
    runs.push_back(std::move(run));
  }
  if (runs.size() < 2)
    fail("rom: dataset ", o.baseline_data, " has ", runs.size(),
         " training runs; look-up and interpolation need at least two");
  return runs;
}

}  // namespace

BaselineInputs read_baseline_inputs(const RomEvalOptions& o, const RomSetup& setup) {
  BaselineInputs in;
  if (o.baseline_data.empty() && o.coarse_scene.empty() && o.coarse_factor == 0) return in;
  if (!o.full_order && o.truth_path.empty())
    fail("rom: the baselines need a ground truth (--truth, or the full-order run)");
  if (!o.baseline_data.empty()) in.runs = read_training_runs(o, setup);
  if (!o.coarse_scene.empty() || o.coarse_factor > 0) {
    // Where the coarse engine is optional and this scene is coarsened, a factor it cannot build
    // (a body inside the coarser wall band: jelly_small at 1.5x) steps down by tenths to 1.1, and
    // the report says which factor ran.
    std::vector<double> factors{o.coarse_factor};
    if (o.coarse_optional && o.coarse_scene.empty())
      for (int tenths = int(std::ceil(o.coarse_factor * 10 - 1e-9)) - 1; tenths >= 11; --tenths)
        factors.push_back(tenths / 10.0);
    std::string first_error;
    for (double factor : factors) {
      RomEvalOptions at = o;
      at.coarse_factor = factor;
      try {
        read_coarse_scene(at, setup, in);
      } catch (const Error& e) {
        if (!o.coarse_optional) throw;
        in.coarse.reset();
        if (first_error.empty()) first_error = e.what();
        continue;
      }
      if (factor != o.coarse_factor) {
        char note[160];
        std::snprintf(note, sizeof note,
                      "the coarse engine runs at %gx dx, the coarsest that builds: at %gx ", factor,
                      o.coarse_factor);
        in.coarse_note = note + first_error;
      }
      break;
    }
    if (!in.coarse) in.coarse_skipped = "coarse engine not measured: " + first_error;
  }
  return in;
}

}  // namespace nsf
