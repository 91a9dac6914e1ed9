// Text on pictures (io/text.h): a real anti-aliased font with lower case, and the labels built on
// it (legend.h) naming the quantity, not the scene's internals.
#include <gtest/gtest.h>

#include <filesystem>

#include "cli_runner.h"
#include "io/image.h"
#include "io/legend.h"
#include "io/run_render.h"
#include "io/scene_hints.h"
#include "io/text.h"
#include "synthetic_run.h"

namespace nsf {
namespace {

namespace fs = std::filesystem;

const Rgb kWhite{255, 255, 255};

// Where `text` leaves ink on a white picture: one flag per pixel.
std::vector<bool> ink(const std::string& text, double size, int w = 60, int h = 40) {
  Image img(w, h, kWhite);
  draw_text(img, 4, 4, text, {0, 0, 0}, size);
  std::vector<bool> mask;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) mask.push_back(img.at(x, y) != kWhite);
  return mask;
}

int count(const std::vector<bool>& m) {
  return static_cast<int>(std::count(m.begin(), m.end(), true));
}

int differ(const std::vector<bool>& a, const std::vector<bool>& b) {
  int n = 0;
  for (size_t i = 0; i < a.size(); ++i) n += a[i] != b[i];
  return n;
}

TEST(Text, DrawsGlyphsInsideTheLineBoxOnly) {
  Image img(200, 40, kWhite);
  const std::string s = "t = 0.300 s  (kPa) jg";
  draw_text(img, 5, 6, s, {0, 0, 0}, 16);
  const int w = text_width(s, 16), h = text_height(16);
  EXPECT_GE(h, 16);
  EXPECT_LE(h, 22);
  int inside = 0, outside = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      if (img.at(x, y) == kWhite) continue;
      (x >= 5 && x < 5 + w && y >= 6 && y < 6 + h ? inside : outside) += 1;
    }
  EXPECT_GT(inside, 100);
  EXPECT_EQ(outside, 0);
}

TEST(Text, LowerCaseIsItsOwnShape) {
  // The old 5x7 font drew every letter in upper case: "t" was "T".
  EXPECT_GT(differ(ink("t", 20), ink("T", 20)), 10);
  EXPECT_GT(differ(ink("s", 20), ink("S", 20)), 10);
  EXPECT_NE(text_width("kpa", 20), text_width("KPA", 20));
  EXPECT_LT(text_width("kpa", 20), text_width("KPA", 20));
}

TEST(Text, IsAntiAliasedAndBlendedIntoTheBackground) {
  Image img(80, 30, {200, 0, 0});
  draw_text(img, 2, 2, "Mises", {0, 0, 200}, 18);
  int partial = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const Rgb c = img.at(x, y);
      partial += c.r > 0 && c.r < 200 && c.b > 0 && c.b < 200;  // part text, part background
      EXPECT_EQ(c.g, 0);
    }
  EXPECT_GT(partial, 20);
}

TEST(Text, GreekAndOtherCharactersHaveGlyphs) {
  // μ is a glyph of its own, not the missing-glyph box that an unassigned code point gets.
  const std::vector<bool> mu = ink("μ", 24), u = ink("u", 24), missing = ink("\xEE\x80\x80", 24);
  EXPECT_GT(count(mu), 10);
  EXPECT_GT(differ(mu, u), 10);
  EXPECT_GT(differ(mu, missing), 10);
  // A malformed UTF-8 byte is drawn as a replacement, not skipped and not a crash.
  EXPECT_GT(text_width("a\xFF"
                       "b",
                       16),
            text_width("ab", 16));
}

TEST(Text, BiggerSizesDrawBiggerText) {
  EXPECT_GT(text_width("speed (m/s)", 24), 1.7 * text_width("speed (m/s)", 12));
  EXPECT_GT(text_height(24), text_height(12));
  EXPECT_EQ(text_width("", 12), 0);
  EXPECT_TRUE(fs::exists(font_path()));
}

TEST(Legend, ObjectsAreNamedByIndexAndMaterialNotByShapeType) {
  const SceneHints h = scene_hints(R"({"objects": [
      {"shape": {"type": "difference", "children": []}, "material": {"type": "von_mises"}},
      {"shape": {"type": "union", "children": []}, "material": {"type": "drucker_prager"}},
      {"shape": {"type": "box"}, "material": {"type": "von_mises"}}]})",
                                   0.02);
  ASSERT_EQ(h.object_names.size(), 3u);
  EXPECT_EQ(h.object_names[0], "object 0 (von Mises)");
  EXPECT_EQ(h.object_names[1], "object 1 (Drucker–Prager)");
  for (const std::string& n : h.object_names)
    for (const char* shape : {"difference", "DIFFERENCE", "union", "box"})
      EXPECT_EQ(n.find(shape), std::string::npos) << n;
  EXPECT_EQ(h.material_names, (std::vector<std::string>{"von Mises", "Drucker–Prager"}));
}

TEST(Legend, TitlesNameTheQuantityAndItsUnit) {
  const fs::path d = testing::fresh_dir("legend_titles");
  const std::string path = (d / "run.h5").string();
  testing::write_synthetic_run(path, 2);
  const RunReader run(path);
  RunRenderOptions o;
  o.color = ColorBy::Object;
  const RenderPlan objects = plan_render(run, {0, 1}, o);
  EXPECT_EQ(objects.legend_title, "colour: object");
  ASSERT_EQ(objects.legend.size(), 2u);
  EXPECT_EQ(objects.legend[0].name, "object 0 (fixed corotated)");
  EXPECT_EQ(objects.legend[1].name, "object 1 (Drucker–Prager)");
  o.color = ColorBy::Material;
  EXPECT_EQ(plan_render(run, {0, 1}, o).legend_title, "colour: material");
  o.color = ColorBy::Speed;
  EXPECT_EQ(plan_render(run, {0, 1}, o).legend_title, "speed (m/s)");
  o.color = ColorBy::Stress;
  const RenderPlan stress = plan_render(run, {0, 1}, o);
  EXPECT_EQ(stress.legend_title,
            stress.hi >= 1e3 ? "von Mises stress (kPa)" : "von Mises stress (Pa)");
  fs::remove_all(d);
}

TEST(Legend, LabelsGoBelowTheLegendWhereThePictureIsTooNarrowForBoth) {
  const std::vector<LegendEntry> entries = {{Color(0.2f, 0.4f, 0.7f), "object 0 (fixed corotated)"},
                                            {Color(1.0f, 0.5f, 0.1f), "object 1 (von Mises)"}};
  const std::string when = "t = 0.000 s    frame 0/32";
  const double size = 12;
  for (const int w : {240, 800}) {
    const Rgb grey{128, 128, 128};
    Image img(w, 180, grey);
    const LegendBox box = draw_swatches(img, "colour: object", entries, size);
    // The box holds everything the legend drew.
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x)
        if (x < box.left || y >= box.bottom) {
          ASSERT_EQ(img.at(x, y), grey) << x << "," << y;
        }
    const int top = labels_top(box, text_width(when, size), size);
    draw_label(img, label_margin(size), top, when, size);
    if (w == 800) {
      EXPECT_EQ(top, label_margin(size)) << "room beside the legend: the label stays at the top";
    } else {
      EXPECT_GT(top, box.bottom) << "no room beside it: the label goes below the legend";
    }
  }
}

}  // namespace
}  // namespace nsf
