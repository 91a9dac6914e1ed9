#pragma once
// Labels on pictures ("ground truth", "ROM", "t = 0.25 s") with a built-in 5x7 pixel font, so
// rendering needs no font files. Upper-case letters, digits and common punctuation; lower case
// is drawn as upper case, anything else as '?'.
#include <string>

#include "io/image.h"

namespace nsf {

// Draws text with its top-left corner at (x, y); each font pixel becomes scale x scale pixels.
// Pixels outside the image are clipped.
void draw_text(Image& img, int x, int y, const std::string& text, Rgb color, int scale = 2);
int text_width(const std::string& text, int scale = 2);
int text_height(int scale = 2);

}  // namespace nsf
