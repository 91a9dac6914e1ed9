#pragma once
// Turns a numbered PNG sequence into an animation with the `ffmpeg` executable. Shelling out
// keeps libav* out of the build; without ffmpeg the frames are still there to view or encode.
#include <string>

#include "core/process.h"  // find_on_path, for callers looking for ffmpeg

namespace nsf {

struct VideoJob {
  std::string pattern;  // printf pattern of the frames, e.g. "out/frame_%04d.png", numbered from 0
  int frame_count = 0;
  int fps = 24;
  std::string out_stem;  // output without extension; ".mp4" or ".gif" is appended
  bool gif = false;      // true: skip MP4 and write a GIF
};

struct VideoResult {
  std::string path;         // the file written
  std::string mp4_failure;  // why a GIF was written instead of the MP4 asked for; "" if it was not
};

// Writes <out_stem>.mp4 (H.264, yuv420p, so every player and browser shows it) or, when asked or
// when this ffmpeg cannot encode H.264, <out_stem>.gif. Atomic: ffmpeg writes a temp name that
// is renamed on success. Fails with ffmpeg's own message when neither works.
VideoResult encode_video(const std::string& ffmpeg, const VideoJob& job);

}  // namespace nsf
