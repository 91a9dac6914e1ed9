#include "io/legend.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "io/text.h"

namespace nsf {

namespace {

const Rgb kInk = {35, 35, 40};

Rgb to_rgb(const Color& c) {
  const auto byte = [](float v) {
    return static_cast<uint8_t>(std::clamp(v * 255.0f + 0.5f, 0.0f, 255.0f));
  };
  return {byte(c.x()), byte(c.y()), byte(c.z())};
}

// Lightens a rectangle towards white: a backdrop that keeps the scene faintly visible.
void panel(Image& img, int x0, int y0, int x1, int y1) {
  x0 = std::max(x0, 0), y0 = std::max(y0, 0);
  x1 = std::min(x1, img.width), y1 = std::min(y1, img.height);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const Rgb c = img.at(x, y);
      const auto mix = [](uint8_t v) { return static_cast<uint8_t>(v / 5 + 255 * 4 / 5); };
      img.set(x, y, {mix(c.r), mix(c.g), mix(c.b)});
    }
}

void fill(Image& img, int x0, int y0, int x1, int y1, Rgb c) {
  for (int y = std::max(y0, 0); y < std::min(y1, img.height); ++y)
    for (int x = std::max(x0, 0); x < std::min(x1, img.width); ++x) img.set(x, y, c);
}

void frame(Image& img, int x0, int y0, int x1, int y1, Rgb c) {
  fill(img, x0, y0, x1, y0 + 1, c);
  fill(img, x0, y1 - 1, x1, y1, c);
  fill(img, x0, y0, x0 + 1, y1, c);
  fill(img, x1 - 1, y0, x1, y1, c);
}

// The padding around text of `size`.
int gap(double size) {
  return std::max(1, static_cast<int>(std::lround(0.3 * size)));
}

}  // namespace

std::vector<double> nice_ticks(double lo, double hi, int target) {
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi)) return {lo};
  const double raw = (hi - lo) / std::max(target - 1, 1);
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  const double m = raw / p;
  const double step = p * (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10);
  std::vector<double> out;
  // A hair of slack so that an end which is itself round (0, 1.5) gets its tick.
  for (double k = std::ceil(lo / step - 1e-9); k * step <= hi + 1e-9 * step; k += 1)
    out.push_back(k * step == 0 ? 0.0 : k * step);  // no "-0"
  return out;
}

std::string format_tick(double value, double spacing) {
  char buf[32];
  const double mag = std::max(std::abs(value), std::abs(spacing));
  if (value == 0) return "0";
  if (mag >= 1e6 || mag < 1e-3) {
    std::snprintf(buf, sizeof buf, "%.2g", value);
  } else {
    const int decimals = std::max(0, -static_cast<int>(std::floor(std::log10(spacing) + 1e-9)));
    std::snprintf(buf, sizeof buf, "%.*f", decimals, value);
  }
  return buf;
}

int label_margin(double size) {
  return std::max(2, static_cast<int>(std::lround(0.6 * size)));
}

int labels_top(const LegendBox& legend, int width, double size) {
  const int m = label_margin(size), pad = gap(size);
  return m + width + pad + m > legend.left ? legend.bottom + m : m;
}

void draw_label(Image& img, int x, int y, const std::string& text, double size) {
  const int pad = gap(size);
  panel(img, x - pad, y - pad, x + text_width(text, size) + pad, y + text_height(size) + pad);
  draw_text(img, x, y, text, kInk, size);
}

LegendBox draw_colorbar(Image& img, double lo, double hi, const std::string& title, double size,
                        bool clipped) {
  const int margin = label_margin(size), pad = gap(size), line = text_height(size);
  const int bar_w = std::max(4, static_cast<int>(std::lround(0.6 * size)));
  const int bar_h = std::max(img.height / 2, 40);
  const double span = hi > lo ? hi - lo : 1.0;
  std::vector<double> ticks = nice_ticks(lo, hi);
  const double spacing = ticks.size() > 1 ? ticks[1] - ticks[0] : span;
  const std::string top_label = ">" + format_tick(hi, spacing / 10);
  int label_w = clipped ? text_width(top_label, size) : 0;
  for (double t : ticks) label_w = std::max(label_w, text_width(format_tick(t, spacing), size));
  const int block_w = std::max(bar_w + pad + label_w, text_width(title, size));
  const int x0 = img.width - margin - block_w;
  const int y0 = margin + line + 2 * pad;  // below the title
  panel(img, x0 - pad, margin - pad, x0 + block_w + pad, y0 + bar_h + line / 2 + pad);
  draw_text(img, x0, margin, title, kInk, size);
  for (int y = 0; y < bar_h; ++y) {
    const Rgb c = to_rgb(viridis(1.0 - static_cast<double>(y) / std::max(bar_h - 1, 1)));
    fill(img, x0, y0 + y, x0 + bar_w, y0 + y + 1, c);
  }
  frame(img, x0, y0, x0 + bar_w, y0 + bar_h, kInk);
  const auto tick = [&](double t, const std::string& label) {
    const int y = y0 + static_cast<int>(std::lround((1 - (t - lo) / span) * (bar_h - 1)));
    fill(img, x0 + bar_w, y, x0 + bar_w + pad / 2, y + std::max(pad / 4, 1), kInk);
    draw_text(img, x0 + bar_w + pad, y - line / 2, label, kInk, size);
  };
  // A round tick too close to the ">hi" label would print on top of it.
  const double room = 1.2 * line * span / bar_h;
  for (double t : ticks)
    if (!clipped || t < hi - room) tick(t, format_tick(t, spacing));
  if (clipped) tick(hi, top_label);
  return {x0 - pad, y0 + bar_h + line / 2 + pad};
}

LegendBox draw_swatches(Image& img, const std::string& title,
                        const std::vector<LegendEntry>& entries, double size) {
  if (entries.empty()) return {img.width, 0};
  const int margin = label_margin(size), pad = gap(size), line = text_height(size);
  const int box = line * 3 / 4, row = line + pad / 2;
  int block_w = text_width(title, size);
  for (const LegendEntry& e : entries)
    block_w = std::max(block_w, box + pad + text_width(e.name, size));
  const int x0 = img.width - margin - block_w;
  const int y0 = margin + line + pad;  // below the title
  const int bottom = y0 + row * static_cast<int>(entries.size()) + pad / 2;
  panel(img, x0 - pad, margin - pad, x0 + block_w + pad, bottom);
  draw_text(img, x0, margin, title, kInk, size);
  for (size_t i = 0; i < entries.size(); ++i) {
    const int y = y0 + row * static_cast<int>(i);
    const int by = y + (line - box) / 2;
    fill(img, x0, by, x0 + box, by + box, to_rgb(entries[i].color));
    frame(img, x0, by, x0 + box, by + box, kInk);
    draw_text(img, x0 + box + pad, y, entries[i].name, kInk, size);
  }
  return {x0 - pad, bottom};
}

}  // namespace nsf
