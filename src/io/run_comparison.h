#pragma once
// Two runs of one scene shown together — ground truth | reduced order — with one camera, one
// colour scale and a label on each side: a still (a few frames, one run per row) and an
// animation (the two side by side, frame by frame).
#include <string>

#include "io/run_render.h"

namespace nsf {

struct ComparisonFiles {
  std::string still;       // <out_stem>.png
  std::string video;       // <out_stem>.mp4 or .gif; "" without ffmpeg
  std::string frames_dir;  // <out_stem>_frames/: the animation's PNG frames
  std::string note;        // why there is no video, or why it is a GIF
};

// The runs must have the same frame count (same scene); the camera and colour scale come from
// `left` so both sides are drawn alike. Files are written atomically.
ComparisonFiles write_comparison(const std::string& left, const std::string& right,
                                 const std::string& left_label, const std::string& right_label,
                                 const std::string& out_stem, int columns = 5,
                                 RunRenderOptions options = {});

}  // namespace nsf
