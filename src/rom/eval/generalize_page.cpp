// docs/RESULTS.md's section on `nsf generalize`: the scenes' summaries, then their draws by kind.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "rom/eval/generalize.h"

namespace nsf {

namespace {

// A draw's value at `key`: the ROM's δ of a failed draw +∞ (it lost), a value not measured −1.
double value_at(const nlohmann::json& d, const char* key, bool rom) {
  if (rom && d.value("failed", false)) return std::numeric_limits<double>::infinity();
  const nlohmann::json& v = d.contains(key) ? d[key] : nlohmann::json();
  if (v.is_number()) return v.get<double>();
  return rom ? std::numeric_limits<double>::infinity() : -1;
}

// The median of the values measured (a ROM's +∞ included), −1 for none.
double median_measured(const std::vector<double>& v) {
  std::vector<double> kept;
  for (double x : v)
    if (x >= 0) kept.push_back(x);
  return median(kept);
}

// Each scene's draws grouped by perturbation, in the scene's order: which interactions the ROM
// follows and which it does not.
std::string kinds_markdown(const std::vector<nlohmann::json>& rows) {
  std::ostringstream s;
  s << "By kind of perturbation (medians over each kind's draws; wins against look-up):\n\n"
    << "| scene | perturbation | draws | ROM δ | representation | look-up | interp. | wins: "
       "look-up |\n|---|---|---|---|---|---|---|---|\n";
  const auto pct = [](double v) -> std::string {
    if (std::isinf(v)) return "failed";
    return formatted(v >= 0 ? nlohmann::json(v) : nlohmann::json(), 100, "%.2f %%", "—");
  };
  for (const nlohmann::json& j : rows) {
    if (!j.contains("draws")) continue;
    std::vector<std::string> order;
    std::map<std::string, std::vector<const nlohmann::json*>> kinds;
    for (const nlohmann::json& d : j["draws"]) {
      const std::string name = d.value("perturbation", "?");
      if (!kinds.count(name)) order.push_back(name);
      kinds[name].push_back(&d);
    }
    for (const std::string& name : order) {
      std::vector<double> rom, repr, lookup, interp;
      for (const nlohmann::json* d : kinds[name]) {
        rom.push_back(value_at(*d, "delta", true));
        repr.push_back(value_at(*d, "representation_delta", false));
        lookup.push_back(value_at(*d, "lookup_delta", false));
        interp.push_back(value_at(*d, "interp_delta", false));
      }
      const auto [wins, counted] = wins_against(rom, lookup);  // as the summary counts them
      s << "| " << j.value("scene", "?") << " | " << name << " | " << rom.size() << " | "
        << pct(median_measured(rom)) << " | " << pct(median_measured(repr)) << " | "
        << pct(median_measured(lookup)) << " | " << pct(median_measured(interp)) << " | " << wins
        << " of " << counted << " |\n";
    }
  }
  return s.str();
}

}  // namespace

std::string generalize_markdown(const std::vector<nlohmann::json>& in) {
  std::vector<nlohmann::json> rows = in;
  std::sort(rows.begin(), rows.end(), [](const nlohmann::json& a, const nlohmann::json& b) {
    return a.value("scene", "") < b.value("scene", "");
  });
  const auto at = [](const nlohmann::json& j, const char* key) {
    return j.contains(key) ? j[key] : nlohmann::json(nullptr);
  };
  const auto pct = [&](const nlohmann::json& j, const char* key) {
    return formatted(at(j, key), 100, "%.2f %%", "—");
  };
  const auto times = [&](const nlohmann::json& j, const char* key) {
    return formatted(at(j, key), 1, "%.1f×", "—");
  };
  const auto share = [&](const nlohmann::json& j, const char* key) {
    return formatted(at(j, key), 100, "%.0f %%", "—");
  };
  std::ostringstream s;
  s << "## Unseen interactions (`nsf generalize`)\n\n"
    << "Each scene's reduced model on random perturbations outside its sweep (the scene's "
       "`generalize` section: collider speeds, paths and stopping points, throws, slopes, "
       "placements), each draw scored against a fresh full-order run; docs/GENERALIZE.md says "
       "how. δ columns are medians over the draws (a failed draw counts as infinite); wins are "
       "the share of draws where the ROM's δ is below the baseline's. Rows: "
       "`docs/results/generalize/SCENE.json`, each made by the command it names.\n\n"
    << "| scene | draws | ROM δ (worst) | representation | look-up | interp. | coarse | ROM "
       "speed-up | coarse speed-up | real time | wins: look-up / interp. / coarse | bar |\n"
    << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const nlohmann::json& j : rows) {
    const size_t n = j.contains("draws") ? j["draws"].size() : 0;
    const int failed = j.value("failed_draws", 0);
    s << "| " << j.value("scene", "?") << " | " << n
      << (failed ? " (" + std::to_string(failed) + " failed)" : "") << " | "
      << pct(j, "median_delta") << " (" << pct(j, "worst_delta") << ") | "
      << pct(j, "median_representation_delta") << " | " << pct(j, "median_lookup_delta") << " | "
      << pct(j, "median_interp_delta") << " | " << pct(j, "median_coarse_delta") << " | "
      << times(j, "median_speedup") << " | " << times(j, "median_coarse_speedup") << " | "
      << times(j, "median_real_time_factor") << " | " << share(j, "win_rate_lookup") << " / "
      << share(j, "win_rate_interp") << " / " << share(j, "win_rate_coarse") << " | "
      << (j.contains("meets_bar") && j["meets_bar"].value("all", false) ? "met" : "not met")
      << " |\n";
  }
  s << "\n";
  for (const nlohmann::json& j : rows)
    s << "- " << j.value("scene", "?") << ": `" << j.value("command", "") << "`\n";
  s << "\n" << kinds_markdown(rows);
  return s.str();
}

}  // namespace nsf
