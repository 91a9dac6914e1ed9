#include "rom/eval/generalize.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "core/cpu_model.h"
#include "core/error.h"
#include "core/progress.h"
#include "nn/dataset.h"
#include "nn/neural_fields.h"
#include "rom/calibration/rom_calibration.h"
#include "rom/setup/scene_file.h"

namespace nsf {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The bar (#55, "Done when"): what the summary checks each scene against.
constexpr double kMedianDeltaBar = 0.015;      // median δ ≤ 1.5 %
constexpr double kRepresentationFactor = 3.0;  // and ≤ 3× the median representation error
constexpr double kWinRateSweepBar = 0.8;       // beats look-up and interpolation on ≥ 80 %
constexpr double kWinRateCoarseBar = 0.5;      // beats the coarse engine on ≥ 50 %
constexpr double kSpeedupBarSmall = 5.0;       // ≥ 5× full order (small scenes)
constexpr double kSpeedupBarPaper = 10.0;      // ≥ 10× at paper size

nlohmann::json number_or_null(double v) {
  return std::isfinite(v) && v >= 0 ? nlohmann::json(v) : nlohmann::json(nullptr);
}

// Ranks 1…n, ties sharing their mean rank.
std::vector<double> ranks(const std::vector<double>& v) {
  std::vector<size_t> order(v.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return v[a] < v[b]; });
  std::vector<double> r(v.size());
  for (size_t i = 0; i < order.size();) {
    size_t j = i;
    while (j + 1 < order.size() && v[order[j + 1]] == v[order[i]]) ++j;
    for (size_t k = i; k <= j; ++k) r[order[k]] = 0.5 * double(i + j) + 1;
    i = j + 1;
  }
  return r;
}

// Spearman's rank correlation of paired values; NaN for fewer than 3 pairs or a constant side.
double rank_correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const size_t n = a.size();
  if (n < 3 || b.size() != n) return std::nan("");
  const std::vector<double> ra = ranks(a), rb = ranks(b);
  double ma = 0, mb = 0;
  for (size_t i = 0; i < n; ++i) ma += ra[i] / double(n), mb += rb[i] / double(n);
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < n; ++i) {
    sab += (ra[i] - ma) * (rb[i] - mb);
    saa += (ra[i] - ma) * (ra[i] - ma);
    sbb += (rb[i] - mb) * (rb[i] - mb);
  }
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : std::nan("");
}

// The fraction of wins_against's draws that the ROM won; −1 when none counts.
double win_rate(const std::vector<double>& rom, const std::vector<double>& baseline) {
  const auto [wins, counted] = wins_against(rom, baseline);
  return counted ? double(wins) / counted : -1;
}

}  // namespace

double median(std::vector<double> v) {
  if (v.empty()) return -1;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::pair<int, int> wins_against(const std::vector<double>& rom,
                                 const std::vector<double>& baseline) {
  int wins = 0, counted = 0;
  for (size_t i = 0; i < rom.size(); ++i) {
    if (!(baseline[i] >= 0) && std::isfinite(rom[i])) continue;
    ++counted;
    wins += rom[i] < baseline[i];
  }
  return {wins, counted};
}

std::string formatted(const nlohmann::json& v, double scale, const char* fmt, const char* none) {
  char b[32];
  if (!v.is_number()) return none;
  std::snprintf(b, sizeof b, fmt, scale * v.get<double>());
  return b;
}

void set_up_draw(RomEvalOptions& ro, const PerturbationDraw& draw, const SweepSpec* sweep) {
  ro.axes.clear();
  for (size_t k = 0; sweep && k < sweep->vary.size(); ++k) {
    for (std::string& a : expand_templates(sweep->vary[k].set, "v", draw.values.at(k)))
      ro.overrides.push_back(std::move(a));
    ro.axes[sweep->vary[k].name] = draw.values.at(k);
  }
  ro.overrides.insert(ro.overrides.end(), draw.overrides.begin(), draw.overrides.end());
  ro.mu.reset();
  if (sweep) ro.mu = draw.mu;
}

GeneralizeResult run_generalize(const GeneralizeOptions& o) {
  GeneralizeResult res;
  res.model_file = o.model_path;
  res.data_dir = o.data_dir;
  res.scene_file = o.scene_path;
  if (res.scene_file.empty())
    fail(
        "generalize: give the scene file (--scene): the benchmark's perturbations are in its "
        "\"generalize\" section");
  const SceneFile file = read_scene_file(res.scene_file, o.overrides);
  if (!file.sections.generalize)
    fail("generalize: scene ", res.scene_file,
         " has no \"generalize\" section listing the perturbations to draw (docs/GENERALIZE.md)");
  const GeneralizeSpec& spec = *file.sections.generalize;
  res.scene = file.json.value("name", res.scene_file);
  res.seed = o.seed ? *o.seed : spec.seed;
  res.planned = o.draws > 0 ? o.draws : spec.draws;
  const SweepSpec* sweep = file.sections.sweep ? &*file.sections.sweep : nullptr;
  std::vector<PerturbationDraw> draws = plan_draws(spec, sweep, res.planned, res.seed);
  if (!o.only.empty()) {
    for (int k : o.only)
      if (k < 0 || k >= res.planned)
        fail("generalize: draw ", k, " does not exist (draws 0 to ", res.planned - 1, ")");
    draws.erase(std::remove_if(draws.begin(), draws.end(),
                               [&](const PerturbationDraw& d) {
                                 return std::find(o.only.begin(), o.only.end(), d.index) ==
                                        o.only.end();
                               }),
                draws.end());
  }

  // Bad input stops here, not as a failure of every draw: the model (of this scene) and the
  // dataset the baselines play back, whose runs must hold a value of each of the sweep's axes.
  const RomCalibration unseen = rom_calibrations(NeuralFields::load(o.model_path)).unseen;
  if (unseen.table.is_object() && unseen.table.value("seed", res.seed + 1) == res.seed)
    fail("generalize: ", o.model_path, "'s unseen profile was calibrated on the draws of seed ",
         res.seed,
         " (nsf calibrate --unseen): the benchmark scores a model on draws it never saw; give "
         "another --seed, or calibrate with another");
  if (sweep) {
    const Dataset data(o.data_dir);
    for (const ParameterAxis& axis : sweep->vary)
      for (const SimulationFile& run : data.train())
        if (std::none_of(run.box.parameters.begin(), run.box.parameters.end(),
                         [&](const ParameterRange& p) { return p.name == axis.name; }))
          fail("generalize: training run ", run.path, " of ", o.data_dir,
               " has no value of the sweep's axis '", axis.name,
               "': look-up and interpolation play back runs of this scene's own sweep");
  }

  Progress progress("unseen interactions of " + res.scene, long(draws.size()), "draws");
  for (size_t i = 0; i < draws.size(); ++i) {
    GeneralizeDraw g;
    g.draw = draws[i];
    RomEvalOptions ro = o.rom;
    ro.model_path = o.model_path;
    ro.scene_path = res.scene_file;
    ro.overrides = o.overrides;
    set_up_draw(ro, g.draw, sweep);
    ro.full_order = true;
    ro.truth_path.clear();
    ro.quiet = true;  // one progress line, over the draws
    ro.budget = true;
    if (sweep) ro.baseline_data = o.data_dir;
    ro.coarse_scene = o.coarse_scene;
    ro.coarse_factor = o.coarse_scene.empty() ? o.coarse_factor : 0;
    ro.coarse_optional = true;
    try {
      g.report = evaluate_rom(ro);
    } catch (const Error& e) {
      g.error = e.what();
    }
    if (!o.quiet) {
      char line[256];
      if (g.report)
        std::snprintf(line, sizeof line, "draw %d (%s, v = %.4g): delta %.3f%%, %.1fx",
                      g.draw.index, g.draw.perturbation.c_str(), g.draw.value,
                      100 * g.report->delta, g.report->speedup());
      else
        std::snprintf(line, sizeof line, "draw %d (%s, v = %.4g): failed", g.draw.index,
                      g.draw.perturbation.c_str(), g.draw.value);
      progress.update(long(i + 1), line);
    }
    res.draws.push_back(std::move(g));
  }
  if (!o.quiet) progress.finish();
  return res;
}

nlohmann::json generalize_json(const GeneralizeResult& res, const std::string& command) {
  nlohmann::json j;
  j["scene"] = res.scene;
  j["scene_file"] = res.scene_file;
  j["model_file"] = res.model_file;
  j["data"] = res.data_dir;
  j["command"] = command;
  j["seed"] = res.seed;
  j["planned_draws"] = res.planned;
  const bool paper = res.scene.find("_paper") != std::string::npos;
  std::vector<double> delta, repr, proj, speed, rtf, lookup, interp, coarse, coarse_speed;
  // The indicators against δ, over finished draws: the residual, the training distance, and the
  // samples' kinetic energy the inversion loses.
  std::vector<double> ind_delta, ind, dist, energy_lost;
  int failed = 0;
  nlohmann::json rows = nlohmann::json::array();
  for (const GeneralizeDraw& g : res.draws) {
    nlohmann::json d;
    d["index"] = g.draw.index;
    d["perturbation"] = g.draw.perturbation;
    d["value"] = g.draw.value;
    d["mu"] = g.draw.mu;
    if (!g.draw.values.empty()) d["values"] = g.draw.values;
    d["set"] = g.draw.overrides;
    if (!g.report || !(g.report->delta >= 0)) {
      ++failed;
      d["failed"] = true;
      d["error"] = g.report ? "no ground truth to score against" : g.error;
      delta.push_back(kInf);  // a failed run loses to every baseline and counts in the median
      for (auto* v : {&repr, &proj, &speed, &rtf, &lookup, &interp, &coarse, &coarse_speed})
        v->push_back(-1);
      rows.push_back(d);
      continue;
    }
    const RomReport& r = *g.report;
    const Baselines& b = r.baselines;
    // Simulated time over the ROM's wall time: above 1, the ROM runs faster than real time.
    const double rt = r.rom_seconds > 0 ? r.frames * r.frame_dt / r.rom_seconds : -1;
    d["failed"] = false;
    d["delta"] = r.delta;
    d["stress_error"] = number_or_null(r.stress_error);
    d["speedup"] = number_or_null(r.speedup());
    d["real_time_factor"] = number_or_null(rt);
    d["dt_ratio"] = r.dt_ratio;  // the step taken, which "cfl" sets per draw
    d["representation_delta"] = r.budget ? number_or_null(r.budget->encoded.delta) : nullptr;
    d["projection_delta"] = r.budget ? number_or_null(r.budget->projected.delta) : nullptr;
    d["lookup_delta"] = number_or_null(b.lookup_delta);
    d["interp_delta"] = number_or_null(b.interp_delta);
    d["coarse_delta"] = number_or_null(b.coarse_delta);
    d["coarse_speedup"] = number_or_null(r.coarse_speedup());
    d["coarse_scene"] = b.coarse_scene;
    d["indicator"] = r.residual_cells_mean;
    d["indicator_max"] = r.residual_cells_max;
    d["training_distance"] = number_or_null(r.training_distance_mean);
    d["energy_kept"] = r.energy_kept;
    d["rom_seconds"] = r.rom_seconds;
    d["fom_seconds"] = r.fom_seconds;
    d["warnings"] = r.warnings;
    d["recoveries"] = r.recoveries;  // steps the step guard redid (0 unguarded)
    // Whether the draw took a collider out of the box the model was trained on.
    d["outside_training"] = !r.training_note.empty();
    // What of its scene the model's training runs never took (data/scene_family.h), and the
    // settings that followed from it (the scene's rom.unseen profile, or the family's).
    d["outside_family"] = r.outside_family;
    d["profile"] = r.profile;
    rows.push_back(d);
    delta.push_back(r.delta);
    repr.push_back(r.budget ? r.budget->encoded.delta : -1);
    proj.push_back(r.budget ? r.budget->projected.delta : -1);
    speed.push_back(r.speedup());
    rtf.push_back(rt);
    lookup.push_back(b.lookup_delta);
    interp.push_back(b.interp_delta);
    coarse.push_back(b.coarse_delta);
    coarse_speed.push_back(r.coarse_speedup());
    ind_delta.push_back(r.delta);
    ind.push_back(r.residual_cells_mean);
    dist.push_back(r.training_distance_mean);
    energy_lost.push_back(1 - r.energy_kept);
  }
  j["draws"] = rows;
  j["failed_draws"] = failed;
  const auto measured = [](const std::vector<double>& v) {
    std::vector<double> out;
    for (double x : v)
      if (x >= 0 && std::isfinite(x)) out.push_back(x);
    return out;
  };
  const double med = median(delta);  // failed draws count as +∞
  j["median_delta"] = number_or_null(med);
  j["worst_delta"] = delta.empty() ? nlohmann::json(nullptr)
                                   : number_or_null(*std::max_element(delta.begin(), delta.end()));
  const double med_repr = median(measured(repr));
  j["median_representation_delta"] = number_or_null(med_repr);
  j["median_projection_delta"] = number_or_null(median(measured(proj)));
  const double med_speed = median(measured(speed));
  j["median_speedup"] = number_or_null(med_speed);
  j["median_real_time_factor"] = number_or_null(median(measured(rtf)));
  j["median_lookup_delta"] = number_or_null(median(measured(lookup)));
  j["median_interp_delta"] = number_or_null(median(measured(interp)));
  j["median_coarse_delta"] = number_or_null(median(measured(coarse)));
  j["median_coarse_speedup"] = number_or_null(median(measured(coarse_speed)));
  const double wl = win_rate(delta, lookup), wi = win_rate(delta, interp),
               wc = win_rate(delta, coarse);
  j["win_rate_lookup"] = number_or_null(wl);
  j["win_rate_interp"] = number_or_null(wi);
  j["win_rate_coarse"] = number_or_null(wc);
  j["indicator"] =
      "the inversion's rms residual on the samples, in cells (dx), mean over frames: online, "
      "without a truth";
  // A rank correlation in [−1, 1], null where it is not defined (fewer than two draws, ties).
  const auto correlation = [](const std::vector<double>& x, const std::vector<double>& y) {
    const double c = rank_correlation(x, y);
    return std::isfinite(c) ? nlohmann::json(c) : nlohmann::json(nullptr);
  };
  j["indicator_rank_correlation"] = correlation(ind, ind_delta);
  std::vector<double> dist_delta, dist_ok;
  for (size_t i = 0; i < dist.size(); ++i)
    if (dist[i] >= 0) dist_ok.push_back(dist[i]), dist_delta.push_back(ind_delta[i]);
  j["training_distance_rank_correlation"] = correlation(dist_ok, dist_delta);
  j["energy_lost_rank_correlation"] = correlation(energy_lost, ind_delta);
  // The bar of issue #55, each part checked (null: not measured, so not met).
  const double speed_bar = paper ? kSpeedupBarPaper : kSpeedupBarSmall;
  j["bar"] = {{"median_delta", kMedianDeltaBar},
              {"median_delta_over_representation", kRepresentationFactor},
              {"win_rate_lookup", kWinRateSweepBar},
              {"win_rate_interp", kWinRateSweepBar},
              {"win_rate_coarse", kWinRateCoarseBar},
              {"median_speedup", speed_bar}};
  j["meets_bar"] = {{"median_delta", med >= 0 && std::isfinite(med) && med <= kMedianDeltaBar},
                    {"median_delta_over_representation",
                     med_repr > 0 && std::isfinite(med) && med <= kRepresentationFactor * med_repr},
                    {"win_rate_lookup", wl >= kWinRateSweepBar},
                    {"win_rate_interp", wi >= kWinRateSweepBar},
                    {"win_rate_coarse", wc >= kWinRateCoarseBar},
                    {"median_speedup", med_speed >= speed_bar}};
  bool all = true;
  for (const auto& [k, v] : j["meets_bar"].items()) all = all && v.get<bool>();
  j["meets_bar"]["all"] = all;
  for (const GeneralizeDraw& g : res.draws)
    if (g.report) {
      j["cpu"] = g.report->cpu;
      j["threads"] = g.report->threads;
      j["rom"] = {{"samples", g.report->samples},
                  {"dt_ratio", g.report->dt_ratio},
                  {"dt_ratio_source", g.report->dt_ratio_source},
                  {"latent_prior", g.report->latent_prior},
                  {"latent_prior_source", g.report->latent_prior_source},
                  {"sampling", g.report->sampling},
                  {"sample_condition", g.report->sample_condition},
                  {"quadrature_per_cell", g.report->quadrature_per_cell},
                  {"grid", g.report->grid_factor},
                  {"field_sources", g.report->field_sources},
                  {"profile", g.report->profile}};
      break;
    }
  return j;
}

std::string format_generalize(const nlohmann::json& j) {
  std::ostringstream s;
  char line[320];
  const auto pct = [](const nlohmann::json& v) { return formatted(v, 100, "%.2f%%", "-"); };
  const auto num = [](const nlohmann::json& v, const char* fmt) {
    return formatted(v, 1, fmt, "-");
  };
  const auto share = [](const nlohmann::json& v) { return formatted(v, 100, "%.0f%%", "-"); };
  s << "unseen interactions of " << j.value("scene", "") << " (seed " << j.value("seed", 0)
    << "; delta against a fresh full-order run of each draw)\n";
  std::snprintf(line, sizeof line, "  %4s  %-28s %9s %8s  %8s %8s %8s %8s %8s  %7s %9s\n", "draw",
                "perturbation", "v", "mu", "ROM", "repr.", "look-up", "interp.", "coarse",
                "speedup", "indicator");
  s << line;
  for (const auto& d : j.at("draws")) {
    const std::string name = d.value("perturbation", "").substr(0, 28);
    if (d.value("failed", false)) {
      std::snprintf(line, sizeof line, "  %4d  %-28s %9.4g %8.4g  failed: %s\n",
                    d.value("index", 0), name.c_str(), d.value("value", 0.0), d.value("mu", 0.0),
                    d.value("error", "").substr(0, 120).c_str());
    } else {
      std::snprintf(line, sizeof line, "  %4d  %-28s %9.4g %8.4g  %8s %8s %8s %8s %8s  %7s %9s\n",
                    d.value("index", 0), name.c_str(), d.value("value", 0.0), d.value("mu", 0.0),
                    pct(d["delta"]).c_str(), pct(d["representation_delta"]).c_str(),
                    pct(d["lookup_delta"]).c_str(), pct(d["interp_delta"]).c_str(),
                    pct(d["coarse_delta"]).c_str(), num(d["speedup"], "%.1fx").c_str(),
                    num(d["indicator"], "%.3f").c_str());
    }
    s << line;
  }
  std::snprintf(line, sizeof line,
                "  median delta %s (worst %s), median representation %s, median speed-up %s, "
                "real-time factor %s\n",
                pct(j["median_delta"]).c_str(), pct(j["worst_delta"]).c_str(),
                pct(j["median_representation_delta"]).c_str(),
                num(j["median_speedup"], "%.1fx").c_str(),
                num(j["median_real_time_factor"], "%.2f").c_str());
  s << line;
  std::snprintf(line, sizeof line,
                "  ROM wins against look-up %s, interpolation %s, the coarse engine %s of draws; "
                "indicator rank correlation with delta %s\n",
                share(j["win_rate_lookup"]).c_str(), share(j["win_rate_interp"]).c_str(),
                share(j["win_rate_coarse"]).c_str(),
                num(j["indicator_rank_correlation"], "%.2f").c_str());
  s << line;
  s << "  issue #55's bar: " << (j["meets_bar"].value("all", false) ? "met" : "not met");
  std::string missed;
  for (const auto& [k, v] : j["meets_bar"].items())
    if (k != "all" && !v.get<bool>()) missed += (missed.empty() ? "" : ", ") + k;
  if (!missed.empty()) s << " (misses: " << missed << ")";
  s << "\n";
  return s.str();
}

}  // namespace nsf
