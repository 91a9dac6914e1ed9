#pragma once
// Pictures of a saved run, one per frame, ready to be strung into an animation. Everything that
// must not jump between frames — camera, floor, colour scale, legend — is fixed once for the
// whole selection by plan_render; render_run_frame then draws any frame independently (and is
// safe to call from several threads at once).
//
//   RunReader run("run.h5");
//   RunRenderOptions o;  o.color = parse_color_by("speed");
//   const std::vector<size_t> frames = parse_frame_range("::2", run.frame_count());
//   const RenderPlan plan = plan_render(run, frames, o);
//   write_png(render_run_frame(run.read_frame(frames[0]), frames[0], plan), "frame_0000.png");
#include <optional>
#include <string>
#include <vector>

#include "io/collider_shapes.h"
#include "io/image.h"
#include "io/legend.h"
#include "io/png_render.h"
#include "io/run_reader.h"

namespace nsf {

enum class ColorBy { Material, Object, Speed, Stress };

// "material", "object", "speed" or "stress"; fails listing the choices.
ColorBy parse_color_by(const std::string& name);
// "front", "side", "top" or "iso": the direction the camera looks along; fails listing them.
Vec3 parse_view(const std::string& name);
// "eye=x,y,z target=x,y,z [up=x,y,z] [fov=deg]" (or the parts as separate words).
Camera parse_camera_spec(const std::vector<std::string>& words);

struct RunRenderOptions {
  ColorBy color = ColorBy::Object;
  int width = 960, height = 720;
  std::optional<Camera> camera;  // wins over everything
  std::optional<Vec3> view_dir;  // else this framing of the run's bounding box
  double fov_deg = 30;           // for the automatic framings; 0 = orthographic
  // Fixed colour scale for speed/stress; lo >= hi: from the data (0 to a high percentile).
  double range_lo = 0, range_hi = 0;
  bool colliders = true;  // draw the scene's rigid colliders (grips, spatula, brush, planes)
};

struct RenderPlan {
  RenderOptions render;  // camera, floor, particle size
  ColorBy color = ColorBy::Object;
  double lo = 0, hi = 1;  // colour scale for speed/stress
  bool clipped = false;   // some values exceed hi and show in the top colour
  // The first label line, the scene's name; empty: only the time and frame line.
  std::string title;
  // What the colours show, above the legend: "speed (m/s)", "colour: object".
  std::string legend_title;
  std::vector<LegendEntry> legend;  // for object/material colouring
  size_t frame_count = 0;           // frames in the run, for the "frame k/n" label
  double text_size = 13;            // pixel size of the labels (text.h)
  SceneColliders colliders;         // posed at each frame's time; empty with colliders = false
};

// The label text size for a picture of width x height: 1/36 of the smaller side, at least 11 px
// (11 px at 480x360, 20 px at 960x720).
double text_size_for(int width, int height);

// Reads the selected frames once for their bounding box and value range. The camera frames the
// particles and the parts of the colliders close to them. Fails, before anything is drawn, for
// a stored collider the engine cannot build, for a position no simulation could have written
// (check_run_positions), and when the labels' font cannot be opened (text.h).
RenderPlan plan_render(const RunReader& run, const std::vector<size_t>& frames,
                       const RunRenderOptions& options);

// The picture of run frame `k` (its data in `f`), with legend and label.
Image render_run_frame(const RunReader& run, const RunFrame& f, size_t k, const RenderPlan& plan);

}  // namespace nsf
