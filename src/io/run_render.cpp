#include "io/run_render.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <sstream>

#include "core/error.h"
#include "io/colormap.h"
#include "io/position_check.h"
#include "io/scene_hints.h"
#include "io/text.h"

namespace nsf {

namespace {

// The scale tops out at a high percentile, not the maximum: one particle flung off at a wall or
// a stress spike at a contact would otherwise squeeze everything else into the darkest colour.
// Stress is the more skewed (a settled sand column: median 0.2 kPa, 99th percentile 5 kPa, all
// of it in the few layers on the floor), so it is cut lower to leave the body's gradient visible.
double scale_percentile(ColorBy c) {
  return c == ColorBy::Stress ? 0.95 : 0.99;
}

std::vector<double> scalar_field(const RunFrame& f, ColorBy c) {
  return c == ColorBy::Speed ? speeds(f.v) : von_mises(f.tau);
}

double percentile(std::vector<double> v, double q) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double s) { return !std::isfinite(s); }), v.end());
  if (v.empty()) return 0;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
  return v[k];
}

Vec3 parse_vec3(const std::string& key, const std::string& text) {
  std::vector<double> v;
  std::stringstream ss(text);
  std::string part;
  while (std::getline(ss, part, ',')) {
    char* end = nullptr;
    const double d = std::strtod(part.c_str(), &end);
    if (part.empty() || *end != '\0' || !std::isfinite(d))
      fail("--camera: ", key, "=", text, " must be three numbers, e.g. ", key, "=1.5,1,2");
    v.push_back(d);
  }
  if (v.size() != 3) fail("--camera: ", key, "=", text, " must be three numbers x,y,z");
  // Beyond this the view's directions overflow (a camera at 1e300 m used to be reported as "up is
  // parallel to the view direction"); it is also as far as a rendered position may be.
  for (double d : v)
    if (std::abs(d) > kMaxRunCoordinate)
      fail("--camera: ", key, "=", text, " is out of range: each coordinate must lie within ",
           kMaxRunCoordinate, " m of the origin, as every position nsf renders does");
  return Vec3(v[0], v[1], v[2]);
}

// Legend names, and colours, for the indices present in the run.
std::vector<LegendEntry> index_legend(const std::vector<uint16_t>& index,
                                      const std::vector<std::string>& names, const char* kind) {
  constexpr size_t kMaxEntries = 12;  // more would cover the picture
  const std::set<uint16_t> present(index.begin(), index.end());
  std::vector<LegendEntry> out;
  for (uint16_t i : present) {
    if (out.size() == kMaxEntries) {
      out.push_back({Color(1, 1, 1), "+" + std::to_string(present.size() - kMaxEntries) + " more"});
      break;
    }
    out.push_back(
        {palette(i), i < names.size() ? names[i] : std::string(kind) + " " + std::to_string(i)});
  }
  return out;
}

// Grows [lo, hi] to take in the solid colliders (at every selected frame) where they come near
// the particles: a brush or a spatula should be in the picture, but a long rail or a wall must
// not shrink the material to a speck, so each collider counts only within half the particles'
// extent around them.
void include_colliders(const SceneColliders& colliders, const std::vector<double>& times, Vec3& lo,
                       Vec3& hi) {
  const Vec3 margin = (0.5 * (hi - lo)).cwiseMax(1e-3 * (hi - lo).maxCoeff());
  const Vec3 near_lo = lo - margin, near_hi = hi + margin;
  for (double t : times)
    for (const ColliderShape& s : colliders.at(t)) {
      Vec3 a, b;
      if (!bounds(s, a, b)) continue;
      a = a.cwiseMax(near_lo), b = b.cwiseMin(near_hi);
      if ((a.array() > b.array()).any()) continue;  // nowhere near
      lo = lo.cwiseMin(a), hi = hi.cwiseMax(b);
    }
}

// Pa, kPa, MPa or GPa so that the tick labels stay short.
void stress_unit(double hi, double& factor, std::string& unit) {
  factor = 1, unit = "Pa";
  if (hi >= 1e9)
    factor = 1e-9, unit = "GPa";
  else if (hi >= 1e6)
    factor = 1e-6, unit = "MPa";
  else if (hi >= 1e3)
    factor = 1e-3, unit = "kPa";
}

}  // namespace

double text_size_for(int width, int height) {
  return std::max(11.0, std::min(width, height) / 36.0);
}

ColorBy parse_color_by(const std::string& name) {
  if (name == "material") return ColorBy::Material;
  if (name == "object") return ColorBy::Object;
  if (name == "speed") return ColorBy::Speed;
  if (name == "stress") return ColorBy::Stress;
  fail("--color '", name, "' is not a colouring; use material, object, speed or stress");
}

Vec3 parse_view(const std::string& name) {
  // The direction from the eye towards the scene; y is up.
  if (name == "front") return Vec3(0, -0.15, -1);
  if (name == "side") return Vec3(-1, -0.15, 0);
  if (name == "top") return Vec3(0, -1, -0.02);  // a hair off vertical keeps "up" defined
  if (name == "iso") return Vec3(-0.55, -0.5, -1.0);
  fail("--view '", name, "' is not a view; use front, side, top or iso");
}

Camera parse_camera_spec(const std::vector<std::string>& words) {
  Camera cam;
  cam.fov_deg = 40;
  bool eye = false, target = false;
  for (const std::string& w : words) {
    std::stringstream ss(w);
    std::string item;
    while (ss >> item) {
      const size_t eq = item.find('=');
      const std::string key = item.substr(0, eq),
                        value = eq == std::string::npos ? "" : item.substr(eq + 1);
      if (key == "eye") {
        cam.eye = parse_vec3(key, value), eye = true;
      } else if (key == "target") {
        cam.target = parse_vec3(key, value), target = true;
      } else if (key == "up") {
        cam.up = parse_vec3(key, value);
      } else if (key == "fov") {
        char* end = nullptr;
        cam.fov_deg = std::strtod(value.c_str(), &end);
        if (value.empty() || *end != '\0' || !(cam.fov_deg > 0 && cam.fov_deg < 180))
          fail("--camera: fov=", value,
               " must be a vertical field of view in degrees, in (0, 180)");
      } else {
        fail("--camera: '", item, "' is not eye=x,y,z, target=x,y,z, up=x,y,z or fov=degrees");
      }
    }
  }
  if (!eye || !target) fail("--camera needs both eye=x,y,z and target=x,y,z");
  if (!((cam.target - cam.eye).norm() > 0)) fail("--camera: eye and target must differ");
  if (!(cam.up.norm() > 0)) fail("--camera: up must not be zero");
  if (cam.up.normalized().cross((cam.target - cam.eye).normalized()).norm() < 1e-6)
    fail("--camera: up is parallel to the view direction");
  return cam;
}

RenderPlan plan_render(const RunReader& run, const std::vector<size_t>& frames,
                       const RunRenderOptions& o) {
  if (o.width < 16 || o.height < 16 || o.width > 8192 || o.height > 8192)
    fail("--size ", o.width, "x", o.height, " is outside 16x16 to 8192x8192");
  const SceneHints hints = scene_hints(run.scene_json(), run.dx());
  RenderPlan plan;
  plan.color = o.color;
  plan.title = run.scene_name();
  plan.frame_count = run.frame_count();
  plan.text_size = text_size_for(o.width, o.height);
  text_height(plan.text_size);  // a missing font fails here, before anything is drawn

  // One pass over the frames: the box every frame fits in, and the colour scale.
  const bool scalar = o.color == ColorBy::Speed || o.color == ColorBy::Stress;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  double top = 0, max = 0;
  if (o.colliders) plan.colliders = SceneColliders::from_scene_json(run.scene_json());
  const std::vector<double> all_times = run.times();
  std::vector<double> times;
  for (size_t k : frames) {
    times.push_back(all_times.at(k));
    std::vector<Vec3> x;
    if (scalar) {
      RunFrame f = run.read_frame(k);
      const std::vector<double> value = scalar_field(f, o.color);
      top = std::max(top, percentile(value, scale_percentile(o.color)));
      max = std::max(max, percentile(value, 1.0));
      x = std::move(f.x);
    } else {
      x = run.read_positions(k);
    }
    check_run_positions(x, run.path(), k);
    for (const Vec3& p : x) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  }
  // The floor the material rests on, not the lowest particle (which sits a radius above it).
  const double ground = hints.floor_height && *hints.floor_height <= lo.y() + 2 * run.dx()
                            ? *hints.floor_height
                            : lo.y() - hints.particle_radius;
  const double lowest_particle = lo.y();
  include_colliders(plan.colliders, times, lo, hi);
  // What lies under the ground is hidden by it: no room for it in the picture.
  lo.y() = std::max(lo.y(), std::min(ground, lowest_particle));

  RenderOptions& r = plan.render;
  r.width = o.width;
  r.height = o.height;
  r.camera.fov_deg = o.fov_deg;
  r.radius = hints.particle_radius;
  // Pad the box by a particle radius so discs at the edge are not clipped.
  const Vec3 pad = Vec3::Constant(hints.particle_radius);
  frame_box(r, lo - pad, hi + pad, o.view_dir.value_or(Vec3(-0.55, -0.5, -1.0)));
  r.ground_height = ground;
  if (o.camera) {
    r.camera = *o.camera;
  } else if (hints.camera && !o.view_dir) {
    r.camera.eye = hints.camera->eye;
    r.camera.target = hints.camera->target;
    r.camera.up = hints.camera->up;
    r.camera.fov_deg = hints.camera->fov_deg;
  }

  if (scalar) {
    plan.lo = 0;
    plan.hi = top > 0 ? top : 1;
    if (o.range_lo < o.range_hi) plan.lo = o.range_lo, plan.hi = o.range_hi;
    plan.clipped = max > plan.hi;
  }
  if (o.color == ColorBy::Speed) {
    plan.legend_title = "speed (m/s)";
  } else if (o.color == ColorBy::Stress) {
    double factor;
    std::string unit;
    stress_unit(plan.hi, factor, unit);
    plan.legend_title = "von Mises stress (" + unit + ")";
  } else if (o.color == ColorBy::Object) {
    plan.legend_title = "colour: object";
    plan.legend = index_legend(run.object(), hints.object_names, "object");
  } else {
    plan.legend_title = "colour: material";
    plan.legend = index_legend(run.material(), hints.material_names, "material");
  }
  return plan;
}

Image render_run_frame(const RunReader& run, const RunFrame& f, size_t k, const RenderPlan& plan) {
  std::vector<Color> colors;
  switch (plan.color) {
    case ColorBy::Object:
      colors = colors_by_index(run.object());
      break;
    case ColorBy::Material:
      colors = colors_by_index(run.material());
      break;
    case ColorBy::Speed:
    case ColorBy::Stress:
      colors = colors_by_scalar(scalar_field(f, plan.color), plan.lo, plan.hi);
      break;
  }
  RenderOptions r = plan.render;
  r.colliders = plan.colliders.at(f.time);
  Image img = render_particles(f.x, colors, r);

  const double s = plan.text_size;
  LegendBox legend;
  if (plan.color == ColorBy::Stress) {
    double factor;
    std::string unit;
    stress_unit(plan.hi, factor, unit);
    legend =
        draw_colorbar(img, plan.lo * factor, plan.hi * factor, plan.legend_title, s, plan.clipped);
  } else if (plan.color == ColorBy::Speed) {
    legend = draw_colorbar(img, plan.lo, plan.hi, plan.legend_title, s, plan.clipped);
  } else {
    legend = draw_swatches(img, plan.legend_title, plan.legend, s);
  }
  char when[96];
  std::snprintf(when, sizeof when, "t = %.3f s    frame %zu/%zu", f.time, k,
                plan.frame_count > 0 ? plan.frame_count - 1 : 0);
  const int m = label_margin(s);
  const int widest = std::max(text_width(when, s), text_width(plan.title, s));
  int y = labels_top(legend, widest, s);
  if (!plan.title.empty()) {
    draw_label(img, m, y, plan.title, s);
    y += text_height(s) + m;
  }
  draw_label(img, m, y, when, s);
  return img;
}

}  // namespace nsf
