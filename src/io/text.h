#pragma once
// Labels on pictures ("ground truth", "t = 0.250 s", "von Mises stress (kPa)"): UTF-8 text drawn
// with an anti-aliased TrueType font through FreeType and blended into the picture.
//
// The font is DejaVu Sans (Debian's fonts-dejavu-core, installed by scripts/install-deps.sh);
// the environment variable NSF_FONT=/path/to/font.ttf picks another. Without a usable font file
// every function here fails with an Error that names the paths tried and how to fix it.
// All functions are safe to call from several threads at once.
#include <string>

#include "io/image.h"

namespace nsf {

// `size` is the font's pixel size (its em), e.g. 13 for a 480x360 picture. The text's line box
// has its top-left corner at (x, y) and is text_width x text_height pixels; no ink falls outside
// it for ordinary text. Pixels outside the image are clipped.
void draw_text(Image& img, int x, int y, const std::string& utf8, Rgb color, double size);
int text_width(const std::string& utf8, double size);
int text_height(double size);  // one line: the font's ascent plus descent

// The font file in use.
std::string font_path();

}  // namespace nsf
