#pragma once
// Draws rigid colliders into a supersampled picture by casting one ray per pixel: boxes and
// cylinders as translucent shaded solids with dark edges, planes as a translucent patch with a
// grid that fades out around the camera target. Particles nearer than a collider (their depth
// buffer) stay on top; particles behind or inside one show through, tinted. Part of
// render_particles; separate because it is a different way of drawing (rays, not splats).
#include <vector>

#include "io/colormap.h"
#include "io/png_render.h"
#include "io/render_view.h"

namespace nsf {

// rgb: w x h supersampled colours, already holding background and particles; depth: the
// particles' depth along the view direction per pixel (+inf where none). `ss` is the supersampling
// factor, so edges stay about one output pixel wide.
void draw_colliders(std::vector<Color>& rgb, const std::vector<float>& depth, int w, int h, int ss,
                    const View& view, const RenderOptions& opt);

}  // namespace nsf
