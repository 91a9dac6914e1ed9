#include "io/contact_sheet.h"

#include "core/error.h"
#include "io/run_caption.h"

namespace nsf {

std::vector<size_t> spread_frames(size_t frame_count, int columns) {
  std::vector<size_t> out;
  if (frame_count == 0 || columns < 1) return out;
  if (columns == 1 || frame_count == 1) return {frame_count - 1};
  const size_t n = std::min(frame_count, static_cast<size_t>(columns));
  for (size_t c = 0; c < n; ++c) out.push_back(c * (frame_count - 1) / (n - 1));
  return out;
}

double caption_size(double panel_text_size) {
  return 1.2 * panel_text_size;
}

Image contact_sheet(const std::vector<std::string>& run_paths, int columns,
                    const RunRenderOptions& options) {
  if (run_paths.empty()) fail("contact sheet: no run files given");
  if (columns < 1) fail("contact sheet: --columns must be at least 1, got ", columns);
  // Every file is opened (and checked) before anything is drawn.
  std::vector<RunReader> runs;
  std::vector<RunFacts> facts;
  for (const std::string& path : run_paths) {
    runs.emplace_back(path);
    facts.push_back(run_facts(runs.back()));
  }
  const std::vector<std::string> captions = row_captions(facts);
  Image sheet;
  for (size_t r = 0; r < runs.size(); ++r) {
    const RunReader& run = runs[r];
    const std::vector<size_t> frames = spread_frames(run.frame_count(), columns);
    RenderPlan plan = plan_render(run, frames, options);
    plan.title.clear();  // the row's caption names the run
    Image row;
    for (size_t c = 0; c < frames.size(); ++c) {
      Image panel = render_run_frame(run, run.read_frame(frames[c]), frames[c], plan);
      row = c == 0 ? panel : side_by_side(row, panel);
    }
    row = captioned(row, captions[r], caption_size(plan.text_size));
    sheet = r == 0 ? row : above_below(sheet, row, 12);
  }
  return sheet;
}

}  // namespace nsf
