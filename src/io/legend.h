#pragma once
// Keys drawn onto rendered frames so a picture explains itself: a colour bar with ticks for a
// scalar field, or colour swatches with names for objects and materials.
#include <string>
#include <vector>

#include "io/colormap.h"
#include "io/image.h"

namespace nsf {

// `size` is the text's pixel size (text.h); margins and the bar scale with it.

// Where a legend was drawn: its panel's left edge and bottom, so that other labels keep clear.
struct LegendBox {
  int left = 0, bottom = 0;
};

// A vertical viridis bar at the right edge for values in [lo, hi], labelled with round tick
// values, under `title`, which names the quantity and its unit ("speed (m/s)"). `clipped`: some
// values lie above hi; the top end is then labelled ">hi" so that the top colour reads as "this
// much or more".
LegendBox draw_colorbar(Image& img, double lo, double hi, const std::string& title, double size,
                        bool clipped = false);

// One swatch per entry, stacked at the right edge under `title` (what the colours tell apart:
// "colour: object").
struct LegendEntry {
  Color color;
  std::string name;
};
LegendBox draw_swatches(Image& img, const std::string& title,
                        const std::vector<LegendEntry>& entries, double size);

// The top of the labels stacked at the top left, `width` their widest: the margin, or below the
// legend where the picture is too narrow for both side by side.
int labels_top(const LegendBox& legend, int width, double size);

// Text on a pale panel, so it stays legible over particles and ground alike.
void draw_label(Image& img, int x, int y, const std::string& text, double size);

// The margin between a picture's edge and its labels for text of `size`.
int label_margin(double size);

// Round tick values (1, 2 or 5 times a power of ten apart) inside [lo, hi], about `target` many.
std::vector<double> nice_ticks(double lo, double hi, int target = 5);

// A tick value with no more digits than the spacing needs: 0.05, 12, 1500, 2.5e-05.
std::string format_tick(double value, double spacing);

}  // namespace nsf
