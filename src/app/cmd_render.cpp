// `nsf render run.h5 --out frames/`: a PNG per frame and an MP4 (or GIF) of a saved run.
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/common_options.h"
#include "core/error.h"
#include "core/omp_errors.h"
#include "core/path_clash.h"
#include "core/progress.h"
#include "io/frame_range.h"
#include "io/run_reader.h"
#include "io/run_render.h"
#include "io/video.h"

namespace nsf::app {

namespace {

namespace fs = std::filesystem;

struct RenderArgs {
  std::string run, out, color = "object", view, size = "960x720", frames, range;
  std::vector<std::string> camera;
  int fps = 24, threads = 0;
  double fov = 30;
  bool no_video = false, gif = false, quiet = false, no_colliders = false;
};

void parse_size(const std::string& s, int& w, int& h) {
  char x = 0, extra = 0;
  if (std::sscanf(s.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X'))
    fail("--size '", s, "' must look like WIDTHxHEIGHT, e.g. 960x720");
  if (w < 16 || h < 16 || w > 8192 || h > 8192)
    fail("--size ", s, " is outside 16x16 to 8192x8192");
}

void parse_range(const std::string& s, double& lo, double& hi) {
  char colon = 0, extra = 0;
  if (std::sscanf(s.c_str(), "%lf%c%lf%c", &lo, &colon, &hi, &extra) != 3 || colon != ':' ||
      !(lo < hi) || !std::isfinite(lo) || !std::isfinite(hi))
    fail("--range '", s, "' must be LO:HI with finite LO < HI, e.g. 0:2.5");
}

// The drawing options of the flags. A malformed value is a usage error (exit status 2), as
// CLI11's own checks are.
RunRenderOptions render_options(const RenderArgs& a) {
  RunRenderOptions o;
  parse_option_value([&] {
    o.color = parse_color_by(a.color);
    parse_size(a.size, o.width, o.height);
    if (!a.range.empty()) parse_range(a.range, o.range_lo, o.range_hi);
    if (!a.camera.empty() && !a.view.empty()) fail("give either --camera or --view, not both");
    if (!a.camera.empty()) o.camera = parse_camera_spec(a.camera);
    if (!a.view.empty()) o.view_dir = parse_view(a.view);
  });
  o.fov_deg = a.fov;
  o.colliders = !a.no_colliders;
  return o;
}

// Draws `frames` of the run into PNGs named by path(i), several at a time.
void draw_frames(const RunReader& run, const std::vector<size_t>& frames, const RenderPlan& plan,
                 const std::function<std::string(int)>& path, bool quiet) {
  const int n = static_cast<int>(frames.size());
  Progress progress("render", n, "frames");
  int done = 0;
  // One slot per frame for what went wrong in it (a damaged chunk, a full disk), rethrown after
  // the loop: an exception escaping the region or a critical section would abort the program.
  std::vector<std::exception_ptr> errors(n);
  std::atomic<bool> failed{false};
  // Frames are independent; HDF5 is not thread-safe, so only the reads are serialised.
#pragma omp parallel for schedule(dynamic, 1)
  for (int i = 0; i < n; ++i) {
    if (failed) continue;  // the command fails anyway: do not draw the frames not yet begun
    RunFrame f;
#pragma omp critical(nsf_render_read)
    errors[i] = capture_exception([&] { f = run.read_frame(frames[i]); });
    if (!errors[i])
      errors[i] =
          capture_exception([&] { write_png(render_run_frame(run, f, frames[i], plan), path(i)); });
    if (errors[i]) failed = true;
#pragma omp critical(nsf_render_progress)
    if (!quiet) progress.update(++done);
  }
  rethrow_first(errors);
  if (!quiet) progress.finish();
}

// The PNGs frame_%0<digits>d.png in --out as an MP4 (or a GIF), where ffmpeg is on PATH.
void write_video(const RenderArgs& a, int frame_count, int digits) {
  const std::string ffmpeg = find_on_path("ffmpeg");
  if (ffmpeg.empty()) {
    std::printf(
        "note: ffmpeg is not on PATH, so no video was made (the PNGs are complete; "
        "scripts/install-deps.sh installs ffmpeg)\n");
    return;
  }
  VideoJob job;
  // ffmpeg reads its input name as a pattern: a '%' of the directory (or of the working
  // directory, once made absolute) is written "%%", so that it names that directory.
  std::string dir;
  for (char c : fs::absolute(a.out).string())
    dir += c == '%' ? std::string("%%") : std::string(1, c);
  job.pattern = (fs::path(dir) / ("frame_%0" + std::to_string(digits) + "d.png")).string();
  job.frame_count = frame_count;
  job.fps = a.fps;
  job.gif = a.gif;
  job.out_stem = (fs::path(a.out) / fs::path(a.run).stem()).string();
  const VideoResult video = encode_video(ffmpeg, job);
  if (!video.mp4_failure.empty())
    std::printf("note: ffmpeg could not write an MP4, so a GIF was made instead: %s\n",
                video.mp4_failure.c_str());
  std::printf("wrote %s\n", video.path.c_str());
}

// All argument checks and the plan come before anything is written, so a bad option leaves no
// half-made output directory behind.
void run_render(const RenderArgs& a) {
  refuse_path_clash({{"--out", a.out}}, {{"the run", a.run}});
  const int threads = set_threads(a.threads);
  const RunRenderOptions o = render_options(a);
  const RunReader run(a.run);
  if (run.frame_count() == 0) fail(a.run, ": the run has no frames");
  const std::vector<size_t> frames =
      parse_option_value([&] { return parse_frame_range(a.frames, run.frame_count()); });
  const RenderPlan plan = plan_render(run, frames, o);

  std::error_code ec;
  fs::create_directories(a.out, ec);
  if (ec) fail(a.out, ": cannot create the output directory: ", ec.message());
  const int n = static_cast<int>(frames.size());
  const int digits = std::max(4, static_cast<int>(std::to_string(n - 1).size()));
  const auto frame_path = [&](int i) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%0*d.png", digits, i);
    return (fs::path(a.out) / name).string();
  };
  std::fprintf(stderr, "nsf render: %s, %d frames, %zu particles, %dx%d, %d threads\n",
               run.scene_name().c_str(), n, run.particle_count(), o.width, o.height, threads);
  draw_frames(run, frames, plan, frame_path, a.quiet);
  std::printf("wrote %d frames: %s\n", n, frame_path(0).c_str());
  if (!a.no_video) write_video(a, n, digits);
}

}  // namespace

void add_render_command(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* cmd = app.add_subcommand("render", "Render a run's frames to PNGs and a video");
  cmd->add_option("run", args->run, "Run file written by `nsf simulate` (HDF5)")->required();
  cmd->add_option("--out,-o", args->out, "Output directory for frame_0000.png ... and the video")
      ->required();
  cmd->add_option("--color,-c", args->color, "Colour by material, object, speed or stress")
      ->capture_default_str()
      ->check(CLI::IsMember({"material", "object", "speed", "stress"}));
  cmd->add_option("--camera", args->camera,
                  "Camera: eye=x,y,z target=x,y,z [up=x,y,z] [fov=degrees]")
      ->expected(1, 4);
  cmd->add_option("--view", args->view,
                  "Frame the whole run from the front, side, top or iso (default: the scene's "
                  "camera if it has one, else iso)")
      ->check(CLI::IsMember({"front", "side", "top", "iso"}));
  cmd->add_option("--fov", args->fov,
                  "Field of view of --view framings, degrees (0 = orthographic)")
      ->check(in_range(0.0, 120.0))
      ->capture_default_str();
  cmd->add_option("--size", args->size, "Picture size WIDTHxHEIGHT")->capture_default_str();
  cmd->add_option("--frames", args->frames, "Frames a:b:step, Python slice rules (default: all)");
  cmd->add_option(
      "--range", args->range,
      "Fixed colour scale LO:HI for speed (m/s) or stress (Pa) (default: from the run)");
  cmd->add_option("--fps", args->fps, "Video frame rate")
      ->check(in_range(1, 240))
      ->capture_default_str();
  cmd->add_flag("--no-video", args->no_video, "Only the PNGs");
  cmd->add_flag("--no-colliders", args->no_colliders,
                "Draw only the particles, not the scene's rigid colliders");
  cmd->add_flag("--gif", args->gif, "An animated GIF instead of an MP4");
  add_threads_option(cmd, args->threads, "OpenMP threads");
  add_quiet_flag(cmd, args->quiet);
  cmd->callback([args] { run_render(*args); });
}

}  // namespace nsf::app
