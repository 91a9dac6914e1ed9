#include "io/run_comparison.h"

#include <cstdio>
#include <filesystem>

#include "core/error.h"
#include "io/contact_sheet.h"
#include "io/legend.h"
#include "io/run_caption.h"
#include "io/text.h"
#include "io/video.h"

namespace nsf {

namespace {

// The source's name at the bottom left of an animation frame.
Image labelled(Image img, const std::string& label, double size) {
  const int m = label_margin(size);
  draw_label(img, m, img.height - m - text_height(size), label, size);
  return img;
}

}  // namespace

ComparisonFiles write_comparison(const std::string& left, const std::string& right,
                                 const std::string& left_label, const std::string& right_label,
                                 const std::string& out_stem, int columns,
                                 RunRenderOptions options) {
  RunReader a(left), b(right);
  if (a.frame_count() != b.frame_count())
    fail("comparison: ", left, " has ", a.frame_count(), " frames but ", right, " has ",
         b.frame_count(), "; compare two runs of the same scene");
  std::vector<size_t> all(a.frame_count());
  for (size_t k = 0; k < all.size(); ++k) all[k] = k;
  ComparisonFiles out;

  // Still: a row of frames per run.
  options.width = 480, options.height = 360;
  const std::vector<size_t> picks = spread_frames(a.frame_count(), columns);
  RenderPlan still_plan = plan_render(a, all, options);
  still_plan.title.clear();  // each row's caption names its run
  Image rows[2];
  const RunReader* runs[2] = {&a, &b};
  const std::string labels[2] = {left_label, right_label};
  for (int r = 0; r < 2; ++r) {
    for (size_t c = 0; c < picks.size(); ++c) {
      Image panel = render_run_frame(*runs[r], runs[r]->read_frame(picks[c]), picks[c], still_plan);
      rows[r] = c == 0 ? panel : side_by_side(rows[r], panel);
    }
    rows[r] = captioned(rows[r], labels[r] + " · " + run_description(run_facts(*runs[r])),
                        caption_size(still_plan.text_size));
  }
  out.still = out_stem + ".png";
  write_png(above_below(rows[0], rows[1], 12), out.still);

  // Animation: both runs side by side in every frame.
  options.width = 640, options.height = 480;
  const RenderPlan plan = plan_render(a, all, options);
  out.frames_dir = out_stem + "_frames";
  std::filesystem::create_directories(out.frames_dir);
  for (size_t k = 0; k < all.size(); ++k) {
    const Image l =
        labelled(render_run_frame(a, a.read_frame(k), k, plan), left_label, plan.text_size);
    const Image r =
        labelled(render_run_frame(b, b.read_frame(k), k, plan), right_label, plan.text_size);
    char name[32];
    std::snprintf(name, sizeof name, "/frame_%04zu.png", k);
    write_png(side_by_side(l, r), out.frames_dir + name);
  }
  const std::string ffmpeg = find_on_path("ffmpeg");
  if (ffmpeg.empty()) {
    out.note = "ffmpeg not found: the animation's frames are in " + out.frames_dir;
    return out;
  }
  VideoJob job;
  job.pattern = out.frames_dir + "/frame_%04d.png";
  job.frame_count = int(all.size());
  job.fps = 12;
  job.out_stem = out_stem;
  const VideoResult v = encode_video(ffmpeg, job);
  out.video = v.path;
  out.note = v.mp4_failure;
  return out;
}

}  // namespace nsf
