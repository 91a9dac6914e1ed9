#include "io/text.h"

#include <ft2build.h>
#include FT_FREETYPE_H

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <mutex>
#include <vector>

#include "core/error.h"

namespace nsf {

namespace {

// Where Debian (fonts-dejavu-core) and other distributions put DejaVu Sans.
const char* const kFontFiles[] = {
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",   // Debian, Ubuntu
    "/usr/share/fonts/TTF/DejaVuSans.ttf",               // Arch
    "/usr/share/fonts/dejavu-sans-fonts/DejaVuSans.ttf"  // Fedora
};

// One face for the whole process, never freed (pictures may be drawn until exit). FreeType
// faces are not thread-safe, so every use holds the mutex.
struct Font {
  FT_Library library = nullptr;
  FT_Face face = nullptr;
  std::string path;
  std::mutex mutex;
};

Font* open_font() {
  auto* f = new Font;
  if (FT_Init_FreeType(&f->library) != 0) fail("picture text: FreeType failed to start");
  const char* env = std::getenv("NSF_FONT");
  std::vector<std::string> tried;
  if (env && *env) {
    tried.push_back(env);
  } else {
    for (const char* p : kFontFiles) tried.push_back(p);
  }
  for (const std::string& p : tried)
    if (FT_New_Face(f->library, p.c_str(), 0, &f->face) == 0) {
      f->path = p;
      return f;
    }
  FT_Done_FreeType(f->library);
  delete f;
  if (env && *env)
    fail("picture text: NSF_FONT=", env, " is not a font file FreeType can open (a .ttf or .otf)");
  std::string list;
  for (const std::string& p : tried) list += (list.empty() ? "" : ", ") + p;
  fail("picture text needs the font DejaVu Sans and found none (tried ", list,
       "): install Debian's fonts-dejavu-core (bash scripts/install-deps.sh), or set NSF_FONT to "
       "a .ttf file");
}

// A failed open throws out of the initialiser, so the next call tries again.
Font& font() {
  static Font* f = open_font();
  return *f;
}

// Decodes UTF-8; a malformed byte becomes U+FFFD.
std::vector<char32_t> code_points(const std::string& s) {
  std::vector<char32_t> out;
  for (size_t i = 0; i < s.size();) {
    const auto b = static_cast<unsigned char>(s[i]);
    const int n = b < 0x80 ? 1 : (b >> 5) == 6 ? 2 : (b >> 4) == 14 ? 3 : (b >> 3) == 30 ? 4 : 0;
    char32_t c = n == 1 ? b : n == 2 ? b & 0x1F : n == 3 ? b & 0x0F : b & 0x07;
    bool ok = n > 0 && i + n <= s.size();
    for (int k = 1; ok && k < n; ++k) {
      const auto t = static_cast<unsigned char>(s[i + k]);
      ok = (t >> 6) == 2;
      c = (c << 6) | (t & 0x3F);
    }
    out.push_back(ok ? c : 0xFFFD);
    i += ok ? n : 1;
  }
  return out;
}

void set_size(Font& f, double size) {
  const double px = std::clamp(std::isfinite(size) ? size : 1.0, 1.0, 1000.0);
  // 26.6 fixed point at 72 dpi: one point is one pixel, and fractional sizes are kept.
  if (FT_Set_Char_Size(f.face, 0, static_cast<FT_F26Dot6>(std::lround(px * 64)), 72, 72) != 0)
    fail("picture text: the font ", f.path, " has no size ", px);
}

int ascent(const Font& f) {
  return static_cast<int>((f.face->size->metrics.ascender + 63) >> 6);
}

int line_height(const Font& f) {
  return static_cast<int>((f.face->size->metrics.ascender - f.face->size->metrics.descender + 63) >>
                          6);
}

// Lays the glyphs out along a baseline at y = 0 starting at x = 0 and calls `draw` with each
// rendered bitmap and its top-left corner. Returns the ink's [left, right) extent joined with the
// advance, so that text_width covers both.
using GlyphFn = std::function<void(const FT_Bitmap&, int x, int y)>;
std::pair<int, int> layout(Font& f, const std::string& text, const GlyphFn& draw) {
  FT_Long pen = 0;  // 26.6
  FT_UInt previous = 0;
  int left = 0, right = 0;
  const bool kerning = FT_HAS_KERNING(f.face);
  for (char32_t c : code_points(text)) {
    const FT_UInt index = FT_Get_Char_Index(f.face, c);
    if (kerning && previous && index) {
      FT_Vector k;
      if (FT_Get_Kerning(f.face, previous, index, FT_KERNING_DEFAULT, &k) == 0) pen += k.x;
    }
    if (FT_Load_Glyph(f.face, index, FT_LOAD_RENDER | FT_LOAD_TARGET_LIGHT) != 0) continue;
    const FT_GlyphSlot g = f.face->glyph;
    const int x = static_cast<int>((pen + 32) >> 6) + g->bitmap_left;
    if (g->bitmap.width > 0) {
      left = std::min(left, x);
      right = std::max(right, x + static_cast<int>(g->bitmap.width));
      if (draw) draw(g->bitmap, x, -g->bitmap_top);
    }
    pen += g->advance.x;
    previous = index;
  }
  right = std::max(right, static_cast<int>((pen + 32) >> 6));
  return {left, right};
}

}  // namespace

void draw_text(Image& img, int x, int y, const std::string& utf8, Rgb color, double size) {
  Font& f = font();
  std::lock_guard<std::mutex> lock(f.mutex);
  set_size(f, size);
  const int left = layout(f, utf8, nullptr).first;  // a glyph reaching left of x ('j') shifts all
  const int x0 = x - left, baseline = y + ascent(f);
  layout(f, utf8, [&](const FT_Bitmap& b, int gx, int gy) {
    if (b.pixel_mode != FT_PIXEL_MODE_GRAY) return;
    for (unsigned row = 0; row < b.rows; ++row)
      for (unsigned col = 0; col < b.width; ++col) {
        const int a = b.buffer[static_cast<long>(row) * b.pitch + col];
        const int px = x0 + gx + static_cast<int>(col), py = baseline + gy + static_cast<int>(row);
        if (a == 0 || !img.contains(px, py)) continue;
        const Rgb bg = img.at(px, py);
        const auto mix = [a](uint8_t fg, uint8_t back) {
          return static_cast<uint8_t>((fg * a + back * (255 - a) + 127) / 255);
        };
        img.set(px, py, {mix(color.r, bg.r), mix(color.g, bg.g), mix(color.b, bg.b)});
      }
  });
}

int text_width(const std::string& utf8, double size) {
  if (utf8.empty()) return 0;
  Font& f = font();
  std::lock_guard<std::mutex> lock(f.mutex);
  set_size(f, size);
  const auto [left, right] = layout(f, utf8, nullptr);
  return right - left;
}

int text_height(double size) {
  Font& f = font();
  std::lock_guard<std::mutex> lock(f.mutex);
  set_size(f, size);
  return line_height(f);
}

std::string font_path() {
  return font().path;
}

}  // namespace nsf
