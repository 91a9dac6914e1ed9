#pragma once
// A contact sheet: one row per run, a few evenly spaced frames per row, so a reader sees many
// simulations at a glance (docs/scenes.png holds the paper's seven scenes).
#include <string>
#include <vector>

#include "io/image.h"
#include "io/run_render.h"

namespace nsf {

// `columns` frames per run from first to last (fewer if a run has fewer frames). Each row keeps
// one camera and colour scale for all its frames, like `nsf render`, and is captioned with what
// tells its run from the others (run_caption.h: scene, μ, simulation or ROM, file).
Image contact_sheet(const std::vector<std::string>& run_paths, int columns,
                    const RunRenderOptions& options);

// The size of a row's caption for panels whose labels have `panel_text_size` (text.h).
double caption_size(double panel_text_size);

// `columns` indices spread evenly over [0, frame_count), first and last included.
std::vector<size_t> spread_frames(size_t frame_count, int columns);

}  // namespace nsf
