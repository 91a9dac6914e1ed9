#include "io/png_render.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "io/collider_draw.h"
#include "io/collider_raycast.h"

namespace nsf {

namespace {

double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

bool finite(const Vec3& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z());
}

// Rough particle radius: half the mean spacing if the particles filled their bounding box.
double guess_radius(const std::vector<Vec3>& x) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  size_t n = 0;
  for (const Vec3& p : x)
    if (finite(p)) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
      ++n;
    }
  if (n < 2) return 0.01;
  const Vec3 ext = hi - lo;
  const double floor = std::max(1e-3 * ext.maxCoeff(), 1e-12);
  const double volume =
      std::max(ext.x(), floor) * std::max(ext.y(), floor) * std::max(ext.z(), floor);
  return 0.55 * std::cbrt(volume / n);
}

// Darkness on the ground under the particles and solid colliders, as if lit from straight
// above: how many particles stand over each cell, or whether a collider does, fading with their
// height, then blurred into a soft blob.
class ShadowMap {
 public:
  ShadowMap(const std::vector<Vec3>& x, double ground, double radius, const RenderOptions& opt) {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const Vec3& p : x)
      if (finite(p) && p.y() > ground - radius) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
    // Particles' shadows fade on the scale of the particles alone, as without colliders.
    const double fade = std::max(0.5 * std::max(hi.x() - lo.x(), hi.z() - lo.z()), 4 * radius);
    // Colliders count only where the ground is drawn, so a long rail cannot blow up the map.
    const Vec3 reach(opt.ground_extent, 0, opt.ground_extent);
    std::vector<const ColliderShape*> solids;
    for (const ColliderShape& c : opt.colliders) {
      Vec3 a, b;
      if (!bounds(c, a, b) || b.y() <= ground) continue;
      a = a.cwiseMax(opt.camera.target - reach), b = b.cwiseMin(opt.camera.target + reach);
      if (a.x() > b.x() || a.z() > b.z()) continue;
      solids.push_back(&c);
      lo = lo.cwiseMin(a), hi = hi.cwiseMax(b);
    }
    if (!(lo.x() <= hi.x())) return;  // nothing above ground
    const double span = std::max(hi.x() - lo.x(), hi.z() - lo.z());
    cell_ = std::max({2 * radius, span / 300, 1e-9});
    const double pad = kPad * cell_;
    x0_ = lo.x() - pad;
    z0_ = lo.z() - pad;
    nx_ = static_cast<int>((hi.x() - lo.x() + 2 * pad) / cell_) + 1;
    nz_ = static_cast<int>((hi.z() - lo.z() + 2 * pad) / cell_) + 1;
    std::vector<double> count(nx_ * nz_, 0),
        lowest(nx_ * nz_, std::numeric_limits<double>::infinity());
    for (const Vec3& p : x) {
      if (!finite(p) || p.y() <= ground - radius) continue;
      const int i = index(p.x(), p.z());
      count[i] += 1;
      lowest[i] = std::min(lowest[i], p.y() - ground);
    }
    dark_.assign(nx_ * nz_, 0);
    for (size_t i = 0; i < dark_.size(); ++i) {
      if (count[i] == 0) continue;
      const double height = std::max(lowest[i] - radius, 0.0);
      dark_[i] = std::min(1.0, count[i] / 2) / (1 + height / fade);
    }
    // A vertical ray from just under the ground finds the collider above each cell; starting
    // below it lets a box standing on the ground shade its own foot. A collider's shadow fades
    // on the scale of the whole picture, not of its own size: a blade or a brush held well above
    // the ground must still be seen to float there.
    const double collider_fade = std::max(fade, opt.ground_extent / 3);
    for (const ColliderShape* c : solids)
      for (int iz = 0; iz < nz_; ++iz)
        for (int ix = 0; ix < nx_; ++ix) {
          const Vec3 o(x0_ + (ix + 0.5) * cell_, ground - 1e-6 * span, z0_ + (iz + 0.5) * cell_);
          ColliderHit hit;
          if (!ray_enters_solid(*c, o, Vec3::UnitY(), hit)) continue;
          double& d = dark_[iz * nx_ + ix];
          d = std::max(d, kColliderShadow / (1 + hit.t / collider_fade));
        }
    blur();
    blur();
  }

  // Bilinear between cell centres: nearest-cell lookup shows the grid as blocky shadow edges.
  double darkness(double x, double z) const {
    if (dark_.empty()) return 0;
    const double fx = (x - x0_) / cell_ - 0.5, fz = (z - z0_) / cell_ - 0.5;
    const int ix = static_cast<int>(std::floor(fx)), iz = static_cast<int>(std::floor(fz));
    const double tx = fx - ix, tz = fz - iz;
    return (1 - tz) * ((1 - tx) * at(ix, iz) + tx * at(ix + 1, iz)) +
           tz * ((1 - tx) * at(ix, iz + 1) + tx * at(ix + 1, iz + 1));
  }

 private:
  static constexpr int kPad = 6;  // cells of margin so the blur has room to fade out
  // Lighter than a dense pile of particles: colliders are drawn translucent too.
  static constexpr double kColliderShadow = 0.7;

  double at(int ix, int iz) const {
    return ix < 0 || iz < 0 || ix >= nx_ || iz >= nz_ ? 0 : dark_[iz * nx_ + ix];
  }

  int index(double x, double z) const {
    const int ix = std::clamp(static_cast<int>((x - x0_) / cell_), 0, nx_ - 1);
    const int iz = std::clamp(static_cast<int>((z - z0_) / cell_), 0, nz_ - 1);
    return iz * nx_ + ix;
  }

  // Separable binomial [1 4 6 4 1] / 16.
  void blur() {
    static constexpr double w[5] = {1 / 16.0, 4 / 16.0, 6 / 16.0, 4 / 16.0, 1 / 16.0};
    std::vector<double> tmp(dark_.size(), 0);
    for (int z = 0; z < nz_; ++z)
      for (int x = 0; x < nx_; ++x)
        for (int k = -2; k <= 2; ++k)
          if (x + k >= 0 && x + k < nx_) tmp[z * nx_ + x] += w[k + 2] * dark_[z * nx_ + x + k];
    std::fill(dark_.begin(), dark_.end(), 0);
    for (int z = 0; z < nz_; ++z)
      for (int x = 0; x < nx_; ++x)
        for (int k = -2; k <= 2; ++k)
          if (z + k >= 0 && z + k < nz_) dark_[z * nx_ + x] += w[k + 2] * tmp[(z + k) * nx_ + x];
  }

  double cell_ = 1, x0_ = 0, z0_ = 0;
  int nx_ = 0, nz_ = 0;
  std::vector<double> dark_;
};

// Sky gradient, or the ground grid fading into it, for every (supersampled) pixel.
void draw_background(std::vector<Color>& rgb, int w, int h, const View& view,
                     const RenderOptions& opt, const ShadowMap* shadows) {
  const Vec3 centre = opt.camera.target;
  for (int py = 0; py < h; ++py) {
    const float t = static_cast<float>(py) / std::max(h - 1, 1);
    const Color sky = (1 - t) * opt.sky_top + t * opt.sky_bottom;
    for (int px = 0; px < w; ++px) {
      Color c = sky;
      Vec3 o, d;
      view.ray(px + 0.5, py + 0.5, o, d);
      const double dist = opt.ground && d.y() < -1e-9 ? (opt.ground_height - o.y()) / d.y() : -1;
      if (dist > 0) {
        const Vec3 p = o + dist * d;
        // Grid lines stay about a pixel wide however far away they are.
        const double pixel =
            1.0 / view.pixels_per_unit(std::max((p - view.eye).dot(view.fwd), 1e-9));
        const double s = opt.grid_spacing;
        const double gx = std::abs(p.x() / s - std::round(p.x() / s)) * s;
        const double gz = std::abs(p.z() / s - std::round(p.z() / s)) * s;
        const double half_line = std::max(0.015 * s, 0.6 * pixel);
        const float line = static_cast<float>(std::min(gx, gz) < half_line);
        Color g = (1 - line) * opt.ground_color + line * opt.grid_color;
        if (shadows) g *= static_cast<float>(1 - 0.45 * shadows->darkness(p.x(), p.z()));
        const double r = std::hypot(p.x() - centre.x(), p.z() - centre.z());
        const float keep =
            static_cast<float>(1 - smoothstep(0.5 * opt.ground_extent, opt.ground_extent, r));
        c = keep * g + (1 - keep) * sky;
      }
      rgb[static_cast<size_t>(py) * w + px] = c;
    }
  }
}

// Particles as discs shaded like spheres, nearest wins per pixel. `depth` (in/out, +inf where
// empty) keeps the nearest depth per pixel for the colliders drawn afterwards.
void splat_particles(std::vector<Color>& rgb, std::vector<float>& depth, int w, int h,
                     const View& view, const std::vector<Vec3>& x, const std::vector<Color>& colors,
                     double radius, double min_radius_px, const Vec3& light_dir) {
  const Vec3 light = light_dir.normalized();
  const Vec3 half = (light - view.fwd).normalized();  // Blinn-Phong half vector
  for (size_t i = 0; i < x.size(); ++i) {
    double sx, sy, z;
    if (!finite(x[i]) || !view.project(x[i], sx, sy, z)) continue;
    const double r = std::max(radius * view.pixels_per_unit(z), min_radius_px);
    const int x0 = std::max(static_cast<int>(std::floor(sx - r)), 0);
    const int x1 = std::min(static_cast<int>(std::ceil(sx + r)), w - 1);
    const int y0 = std::max(static_cast<int>(std::floor(sy - r)), 0);
    const int y1 = std::min(static_cast<int>(std::ceil(sy + r)), h - 1);
    for (int py = y0; py <= y1; ++py)
      for (int px = x0; px <= x1; ++px) {
        const double dx = (px + 0.5 - sx) / r, dy = (sy - py - 0.5) / r;
        const double d2 = dx * dx + dy * dy;
        if (d2 > 1) continue;
        const double nz = std::sqrt(1 - d2);
        const float zp = static_cast<float>(z - radius * nz);
        const size_t k = static_cast<size_t>(py) * w + px;
        if (zp >= depth[k]) continue;
        depth[k] = zp;
        const Vec3 n = dx * view.right + dy * view.up - nz * view.fwd;
        const double diffuse = std::max(n.dot(light), 0.0);
        const double spec = std::pow(std::max(n.dot(half), 0.0), 24);
        rgb[k] = colors[i] * static_cast<float>(0.35 + 0.65 * diffuse) +
                 Color::Constant(static_cast<float>(0.18 * spec));
      }
  }
}

Image downsample(const std::vector<Color>& rgb, int w, int h, int ss) {
  Image img(w / ss, h / ss);
  const float norm = 255.0f / (ss * ss);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      Color sum = Color::Zero();
      for (int j = 0; j < ss; ++j)
        for (int i = 0; i < ss; ++i) sum += rgb[static_cast<size_t>(y * ss + j) * w + x * ss + i];
      const auto byte = [&](float v) {
        return static_cast<uint8_t>(std::clamp(v * norm + 0.5f, 0.0f, 255.0f));
      };
      img.set(x, y, {byte(sum.x()), byte(sum.y()), byte(sum.z())});
    }
  return img;
}

// 1, 2 or 5 times a power of ten, near `x`.
double round_spacing(double x) {
  const double p = std::pow(10.0, std::floor(std::log10(x)));
  const double m = x / p;
  return p * (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10);
}

}  // namespace

void frame_box(RenderOptions& opt, const Vec3& lo, const Vec3& hi, const Vec3& view_dir) {
  if (!(view_dir.norm() > 0)) fail("frame_box: view direction is zero");
  const Vec3 dir = view_dir.normalized();
  const Vec3 centre = 0.5 * (lo + hi);
  const double diag = std::max((hi - lo).norm(), 1e-9);
  // NaN or a box too big for doubles would make the camera fit below search forever.
  if (!std::isfinite(diag) || !lo.allFinite() || !hi.allFinite() || !centre.allFinite())
    fail("frame_box: the box to frame, [", lo.transpose(), "] to [", hi.transpose(),
         "], is not finite");
  Camera& cam = opt.camera;
  cam.target = centre;
  cam.eye = centre - dir * (2 * diag);
  cam.up = Vec3(0, 1, 0);
  cam.ortho_height = 1;                         // placeholder, set below
  const View view(cam, opt.width, opt.height);  // for its orientation only
  std::vector<Vec3> corners;
  double wr = 0, wu = 0;
  for (int c = 0; c < 8; ++c) {
    const Vec3 corner((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(),
                      (c & 4) ? hi.z() : lo.z());
    corners.push_back(corner);
    wr = std::max(wr, 2 * std::abs((corner - centre).dot(view.right)));
    wu = std::max(wu, 2 * std::abs((corner - centre).dot(view.up)));
  }
  const double aspect = static_cast<double>(opt.width) / std::max(opt.height, 1);
  const double margin = 1.15;
  cam.ortho_height = margin * std::max({wu, wr / aspect, 1e-9});
  if (cam.fov_deg > 0) {
    // The nearest eye distance at which every corner lands inside the margin-shrunk picture.
    const auto fits = [&](double dist) {
      Camera c = cam;
      c.eye = centre - dir * dist;
      const View v(c, opt.width, opt.height);
      for (const Vec3& corner : corners) {
        double sx, sy, z;
        if (!v.project(corner, sx, sy, z)) return false;
        if (std::abs(sx - v.cx) * margin > v.cx || std::abs(sy - v.cy) * margin > v.cy)
          return false;
      }
      return true;
    };
    double near = 0, far = diag;
    // A finite box fits within 2^64 diagonals; the bound stops the search whatever the box.
    for (int doubling = 0; !fits(far); ++doubling) {
      if (doubling == 64 || !std::isfinite(2 * far))
        fail("frame_box: no camera distance fits the box [", lo.transpose(), "] to [",
             hi.transpose(), "] in the picture");
      far *= 2;
    }
    for (int it = 0; it < 40; ++it) {
      const double mid = 0.5 * (near + far);
      (fits(mid) ? far : near) = mid;
    }
    cam.eye = centre - dir * far;
  }
  opt.ground_height = lo.y();
  opt.grid_spacing = round_spacing(diag / 8);
  opt.ground_extent = 1.5 * diag;
}

Image render_particles(const std::vector<Vec3>& x, const std::vector<Color>& colors,
                       const RenderOptions& opt) {
  if (colors.size() != x.size()) {
    fail("render: ", x.size(), " particles but ", colors.size(), " colours");
  }
  if (opt.width <= 0 || opt.height <= 0) fail("render: image size ", opt.width, "x", opt.height);
  const int ss = std::clamp(opt.supersample, 1, 4);
  const int w = opt.width * ss, h = opt.height * ss;
  const View view(opt.camera, w, h);
  const double radius = opt.radius > 0 ? opt.radius : guess_radius(x);

  std::vector<Color> rgb(static_cast<size_t>(w) * h);
  if (opt.ground && opt.shadows) {
    const ShadowMap shadows(x, opt.ground_height, radius, opt);
    draw_background(rgb, w, h, view, opt, &shadows);
  } else {
    draw_background(rgb, w, h, view, opt, nullptr);
  }
  std::vector<float> depth(rgb.size(), std::numeric_limits<float>::infinity());
  splat_particles(rgb, depth, w, h, view, x, colors, radius, opt.min_radius_px * ss, opt.light);
  if (!opt.colliders.empty()) draw_colliders(rgb, depth, w, h, ss, view, opt);
  return downsample(rgb, w, h, ss);
}

}  // namespace nsf
