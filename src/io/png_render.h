#pragma once
// A small software renderer for particle pictures: each particle is a disc shaded as a sphere,
// drawn with a z-buffer, over a ground grid with soft contact shadows and a sky gradient, with
// the scene's rigid colliders drawn translucent in front of what they hide. Enough for a human
// to see a block squash or a bar snap, with no GPU or window system.
//
//   RenderOptions opt;
//   frame_box(opt, lo, hi);                 // camera, ground and grid for the box [lo, hi]
//   opt.radius = 0.5 * dx / ppc;
//   opt.colliders = SceneColliders(scene["colliders"]).at(time);   // optional
//   write_png(render_particles(x, colors_by_index(object), opt), "frame.png");
#include <vector>

#include "core/types.h"
#include "io/collider_shapes.h"
#include "io/colormap.h"
#include "io/image.h"
#include "io/render_view.h"

namespace nsf {

struct RenderOptions {
  int width = 800, height = 600;
  Camera camera;
  double radius = 0;           // particle radius in world units; <= 0: a rough guess from spacing
  double min_radius_px = 1.0;  // so far-away or tiny particles never vanish
  int supersample = 2;         // n x n samples per pixel: smooth disc and grid edges
  Vec3 light = Vec3(-0.4, 1.0, 0.6);  // direction towards the light
  Color sky_top = Color(0.96f, 0.97f, 0.99f);
  Color sky_bottom = Color(0.80f, 0.84f, 0.90f);
  bool ground = true;
  double ground_height = 0;
  double grid_spacing = 0.1;
  double ground_extent = 2.0;  // the ground fades into the sky this far from the camera target
  Color ground_color = Color(0.88f, 0.88f, 0.86f);
  Color grid_color = Color(0.70f, 0.71f, 0.72f);
  bool shadows = true;  // soft shadows straight down onto the ground; they show height and contact
  // Rigid colliders at this picture's time. An upward plane at ground_height is the ground
  // itself and is not drawn twice.
  std::vector<ColliderShape> colliders;
  // A neutral steel grey, apart from the particle palette; translucent so that material behind
  // or inside a blade or a brush still shows.
  Color collider_color = Color(0.55f, 0.58f, 0.63f);
  float collider_alpha = 0.55f;
  Color collider_edge_color = Color(0.20f, 0.22f, 0.26f);
  Color plane_color = Color(0.70f, 0.74f, 0.80f);
  float plane_alpha = 0.75f;
};

// Points the camera at the box [lo, hi] from direction `view_dir` (from the eye towards the box)
// and fits it in the picture; puts the ground under the box with a grid of a round spacing. Keeps
// fov_deg, size and colours.
void frame_box(RenderOptions& opt, const Vec3& lo, const Vec3& hi,
               const Vec3& view_dir = Vec3(-0.55, -0.5, -1.0));

// One colour per particle (colors_by_index / colors_by_scalar). Non-finite positions are skipped.
Image render_particles(const std::vector<Vec3>& x, const std::vector<Color>& colors,
                       const RenderOptions& opt);

}  // namespace nsf
