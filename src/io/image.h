#pragma once
// An 8-bit RGB picture and its PNG file I/O. Deliberately minimal: rendering, side-by-side
// comparisons and labels need nothing more.
#include <cstdint>
#include <string>
#include <vector>

namespace nsf {

struct Rgb {
  uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb& o) const { return r == o.r && g == o.g && b == o.b; }
  bool operator!=(const Rgb& o) const { return !(*this == o); }
};

struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  // rows top to bottom, 3 bytes per pixel

  Image() = default;
  Image(int w, int h, Rgb fill = {});
  Rgb at(int x, int y) const {
    const uint8_t* p = &rgb[3 * (static_cast<size_t>(y) * width + x)];
    return {p[0], p[1], p[2]};
  }
  void set(int x, int y, Rgb c) {
    uint8_t* p = &rgb[3 * (static_cast<size_t>(y) * width + x)];
    p[0] = c.r;
    p[1] = c.g;
    p[2] = c.b;
  }
  bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
};

// Writes <path>.tmp and renames it, so a viewer never sees half a PNG.
void write_png(const Image& img, const std::string& path);
// Reads any PNG libpng understands, converted to 8-bit RGB (alpha dropped).
Image read_png(const std::string& path);

// a | b, tops aligned, separated by `gap` pixels; the shorter one is padded with `fill`.
Image side_by_side(const Image& a, const Image& b, int gap = 8, Rgb fill = {255, 255, 255});

// a above b, left edges aligned, separated by `gap` pixels; the narrower one is padded with `fill`.
Image above_below(const Image& a, const Image& b, int gap = 8, Rgb fill = {255, 255, 255});

}  // namespace nsf
