#include "io/contact_sheet.h"

#include "core/error.h"

namespace nsf {

std::vector<size_t> spread_frames(size_t frame_count, int columns) {
  std::vector<size_t> out;
  if (frame_count == 0 || columns < 1) return out;
  if (columns == 1 || frame_count == 1) return {frame_count - 1};
  const size_t n = std::min(frame_count, static_cast<size_t>(columns));
  for (size_t c = 0; c < n; ++c) out.push_back(c * (frame_count - 1) / (n - 1));
  return out;
}

Image contact_sheet(const std::vector<std::string>& run_paths, int columns,
                    const RunRenderOptions& options) {
  if (run_paths.empty()) fail("contact sheet: no run files given");
  if (columns < 1) fail("contact sheet: --columns must be at least 1, got ", columns);
  Image sheet;
  for (size_t r = 0; r < run_paths.size(); ++r) {
    RunReader run(run_paths[r]);
    const std::vector<size_t> frames = spread_frames(run.frame_count(), columns);
    const RenderPlan plan = plan_render(run, frames, options);
    Image row;
    for (size_t c = 0; c < frames.size(); ++c) {
      Image panel = render_run_frame(run, run.read_frame(frames[c]), frames[c], plan);
      row = c == 0 ? panel : side_by_side(row, panel);
    }
    sheet = r == 0 ? row : above_below(sheet, row, 12);
  }
  return sheet;
}

}  // namespace nsf
