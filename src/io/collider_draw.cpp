#include "io/collider_draw.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "io/collider_raycast.h"

namespace nsf {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

// World size of one (supersampled) pixel at a depth.
double world_pixel(const View& view, double depth) {
  return 1.0 / view.pixels_per_unit(std::max(depth, 1e-9));
}

// A unit vector in the plane, horizontal where the plane is not: grid lines along it then run
// level across a slope and the others straight down it, which shows the inclination.
Vec3 plane_axis(const Vec3& n) {
  Vec3 u = n.cross(Vec3::UnitY());
  if (u.norm() < 1e-6) u = n.cross(Vec3::UnitX());
  return u.normalized();
}

// A plane is the boundary of a half-space, infinite: it is drawn as a patch centred under the
// camera target that fades out like the ground does, with a grid of the ground's spacing.
// Returns the colour's opacity (0: not drawn here) and sets t and colour.
float plane_patch(const ColliderShape& s, const Vec3& o, const Vec3& d, const View& view,
                  const RenderOptions& opt, double& t, Color& c) {
  const double nd = s.normal.dot(d);
  if (std::abs(nd) < 1e-9) return 0;
  t = s.normal.dot(s.center - o) / nd;
  if (!(t > 0)) return 0;
  const Vec3 p = o + t * d;
  const Vec3 centre = opt.camera.target - s.normal.dot(opt.camera.target - s.center) * s.normal;
  const Vec3 u = plane_axis(s.normal), v = s.normal.cross(u);
  const Vec3 rel = p - centre;
  const float keep =
      static_cast<float>(1 - smoothstep(0.5 * opt.ground_extent, opt.ground_extent, rel.norm()));
  if (keep <= 0) return 0;
  const double spacing = opt.grid_spacing;
  const double pixel = world_pixel(view, view.depth_of(o, d, t));
  const double half_line = std::max(0.02 * spacing, 0.6 * pixel);
  const auto off_line = [&](double x) {
    return std::abs(x / spacing - std::round(x / spacing)) * spacing;
  };
  const bool line = std::min(off_line(rel.dot(u)), off_line(rel.dot(v))) < half_line;
  const Vec3 light = opt.light.normalized();
  const Vec3 n = nd < 0 ? s.normal : Vec3(-s.normal);  // the side the camera sees
  const float shade = static_cast<float>(0.6 + 0.4 * std::max(n.dot(light), 0.0));
  c = (line ? opt.collider_edge_color : opt.plane_color) * shade;
  return keep * (line ? std::max(opt.plane_alpha, 0.85f) : opt.plane_alpha);
}

// An upward plane at the ground's height is the floor the ground grid already shows.
bool is_drawn_ground(const ColliderShape& s, const RenderOptions& opt) {
  return opt.ground && s.kind == ColliderShape::Kind::Plane && s.normal.y() > 0.999 &&
         std::abs(s.center.y() - opt.ground_height) <= 0.5 * opt.radius + 1e-3 * opt.grid_spacing;
}

// One collider surface on a pixel's ray: where (ray parameter t), its colour and opacity.
struct Layer {
  double t;
  Color color;
  float alpha;
};

}  // namespace

void draw_colliders(std::vector<Color>& rgb, const std::vector<float>& depth, int w, int h, int ss,
                    const View& view, const RenderOptions& opt) {
  std::vector<const ColliderShape*> shapes;
  for (const ColliderShape& s : opt.colliders)
    if (!is_drawn_ground(s, opt)) shapes.push_back(&s);
  if (shapes.empty()) return;
  const Vec3 light = opt.light.normalized();
  const double edge_px = 0.8 * ss;  // half-width of an outline, in supersampled pixels

  std::vector<Layer> layers;
  for (int py = 0; py < h; ++py)
    for (int px = 0; px < w; ++px) {
      Vec3 o, d;
      view.ray(px + 0.5, py + 0.5, o, d);
      const size_t k = static_cast<size_t>(py) * w + px;
      // The ground hides what lies under it, as seen from above.
      double ground_t = kInf;
      if (opt.ground && o.y() > opt.ground_height && d.y() < -1e-12)
        ground_t = (opt.ground_height - o.y()) / d.y();
      layers.clear();
      for (const ColliderShape* s : shapes) {
        const auto visible = [&](double t) {
          return t < ground_t && view.depth_of(o, d, t) < depth[k];
        };
        if (s->kind == ColliderShape::Kind::Plane) {
          double t;
          Color c;
          const float a = plane_patch(*s, o, d, view, opt, t, c);
          if (a > 0 && visible(t)) layers.push_back({t, c, a});
          continue;
        }
        ColliderHit hit;
        if (!ray_enters_solid(*s, o, d, hit) || !visible(hit.t)) continue;
        if (hit.edge < edge_px * world_pixel(view, view.depth_of(o, d, hit.t))) {
          layers.push_back({hit.t, opt.collider_edge_color, 0.9f});
        } else {
          const double diffuse = std::max(hit.normal.dot(light), 0.0);
          const Color c = opt.collider_color * static_cast<float>(0.45 + 0.55 * diffuse);
          layers.push_back({hit.t, c, opt.collider_alpha});
        }
      }
      // Far to near, each over what lies behind it.
      std::sort(layers.begin(), layers.end(),
                [](const Layer& a, const Layer& b) { return a.t > b.t; });
      for (const Layer& l : layers) rgb[k] = (1 - l.alpha) * rgb[k] + l.alpha * l.color;
    }
}

}  // namespace nsf
