#pragma once
// The benchmark of unseen interactions (issue #55, docs/GENERALIZE.md): a reduced model scored on
// cases no training run made. Each draw perturbs the scene in a way its sweep never varies (the
// scene's "generalize" section, data/perturbation_spec.h) at a random μ of the sweep, and is run
// at full order (the truth, and the time to beat), by the ROM, and by the simple alternatives:
// look-up and interpolation of the training runs, and the coarse engine; the error budget gives
// the representation and projection terms (the truth encoded, the truth's samples fitted).
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "data/perturbation_spec.h"
#include "rom/eval/rom_evaluation.h"

namespace nsf {

struct GeneralizeOptions {
  std::string model_path, data_dir;
  std::string scene_path;              // the scene whose "generalize" section is drawn from
  std::vector<std::string> overrides;  // --set, applied before each draw's perturbation
  int draws = 0;                       // 0: the scene's generalize.draws
  std::optional<uint64_t> seed;        // none: the scene's generalize.seed
  std::vector<int> only;               // run only these draws (by index); empty: all
  // The ROM's settings as `nsf rom` takes them (samples, step, latent prior, field sources,
  // threads); the model, scene, overrides, μ, baselines and budget are set per draw.
  RomEvalOptions rom;
  std::string coarse_scene;    // the coarse engine's scene; "": this one, coarse_factor times
  double coarse_factor = 1.5;  //   coarser (as `nsf report` does for small scenes)
  bool quiet = false;
};

struct GeneralizeDraw {
  PerturbationDraw draw;
  std::optional<RomReport> report;  // none when the ROM (or a run it needs) failed
  std::string error;                // why, then
};

struct GeneralizeResult {
  std::string scene, scene_file, model_file, data_dir;
  uint64_t seed = 1;
  int planned = 0;  // draws planned (the scene's or --draws); `draws` holds those run
  std::vector<GeneralizeDraw> draws;
};

// `ro` set up for the case `draw` of a scene whose sweep is `sweep` (none: it has none): the
// sweep's other axes at the draw's values and the perturbation appended to its overrides (μ's
// templates follow when the scene is set up at μ), the axes by name and μ.
void set_up_draw(RomEvalOptions& ro, const PerturbationDraw& draw, const SweepSpec* sweep);

// Plans the draws and runs them in turn, with a progress line; a draw whose ROM fails is recorded
// with its error, and the others still run. Throws nsf::Error for bad input (no "generalize"
// section, a model of another scene, a dataset without μ, a seed whose draws calibrated the model:
// `nsf calibrate --unseen`).
GeneralizeResult run_generalize(const GeneralizeOptions& options);

// The per-draw rows and their summary: medians, worst δ, speed-ups, real-time factor, win rates
// against each baseline, the indicator's rank correlation with δ, and the bar checked.
// `command` is the command line that made it.
nlohmann::json generalize_json(const GeneralizeResult& result, const std::string& command);

// A table of the draws and the summary, for the terminal.
std::string format_generalize(const nlohmann::json& summary);

// docs/RESULTS.md's section on the benchmark (generalize_page.cpp): one line per scene's summary
// (sorted by scene), each naming the command that made it, then the draws by kind of perturbation.
std::string generalize_markdown(const std::vector<nlohmann::json>& summaries);

// `v` (a JSON number) times `scale` through printf's `fmt`, or `none` where it is not a number
// (not measured).
std::string formatted(const nlohmann::json& v, double scale, const char* fmt, const char* none);

// The median of `v`; −1 when it is empty.
double median(std::vector<double> v);

// Over paired draws: those where the ROM's δ is below the baseline's, and those that count. A
// failed ROM (+∞) loses, whether or not the draw got as far as the baseline; other draws without
// the baseline measured (< 0 or NaN) do not count.
std::pair<int, int> wins_against(const std::vector<double>& rom,
                                 const std::vector<double>& baseline);

}  // namespace nsf
