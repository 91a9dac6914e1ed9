#include "io/run_caption.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "io/text.h"

namespace nsf {

RunFacts run_facts(const RunReader& run) {
  RunFacts f;
  f.file = run.path();
  f.scene = run.scene_name();
  f.rom = run.has_attribute("rom");
  // Attributes written by other tools may have another kind: then they are left out.
  const auto text = [&](const char* name) {
    try {
      return run.has_attribute(name) ? run.attribute_string(name) : std::string();
    } catch (const std::exception&) {
      return std::string();
    }
  };
  f.split = text("split");
  f.parameter = text("sweep_parameter");
  if (run.has_attribute("mu")) try {
      f.mu = run.attribute_double("mu");
    } catch (const std::exception&) {
    }
  return f;
}

std::string run_description(const RunFacts& run) {
  std::string out = run.scene;
  if (run.mu && std::isfinite(*run.mu)) {
    char mu[48];
    std::snprintf(mu, sizeof mu, "%.4g", *run.mu);
    out += std::string(" · μ = ") + mu + (run.parameter.empty() ? "" : " (" + run.parameter + ")");
  }
  return out;
}

std::vector<std::string> row_captions(const std::vector<RunFacts>& runs) {
  std::vector<std::string> out;
  for (const RunFacts& r : runs) {
    const std::string name = std::filesystem::path(r.file).filename().string();
    const bool shared =
        std::count_if(runs.begin(), runs.end(), [&](const RunFacts& o) {
          return o.file != r.file && std::filesystem::path(o.file).filename().string() == name;
        }) > 0;
    std::string source = r.rom ? "reduced-order model" : "simulation";
    if (!r.split.empty()) source += ", " + r.split + " run";
    out.push_back(run_description(r) + " · " + source + " · " + (shared ? r.file : name));
  }
  return out;
}

Image captioned(const Image& row, const std::string& caption, double size) {
  const int pad = std::max(2, static_cast<int>(std::lround(0.4 * size)));
  Image band(row.width, text_height(size) + 2 * pad, {255, 255, 255});
  draw_text(band, pad, pad, caption, {35, 35, 40}, size);
  return above_below(band, row, 0);
}

}  // namespace nsf
