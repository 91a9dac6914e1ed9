#include <gtest/gtest.h>

#include <filesystem>

#include "core/error.h"
#include "io/contact_sheet.h"
#include "io/run_caption.h"
#include "io/run_writer.h"
#include "io/text.h"
#include "synthetic_run.h"

namespace nsf {
namespace {

namespace fs = std::filesystem;

TEST(ContactSheet, SpreadsFramesFromFirstToLast) {
  EXPECT_EQ(spread_frames(5, 3), (std::vector<size_t>{0, 2, 4}));
  EXPECT_EQ(spread_frames(41, 4), (std::vector<size_t>{0, 13, 26, 40}));
  EXPECT_EQ(spread_frames(2, 4), (std::vector<size_t>{0, 1}));
  EXPECT_EQ(spread_frames(7, 1), (std::vector<size_t>{6}));
}

TEST(ContactSheet, OneRowPerRunOnePanelPerFrame) {
  const fs::path d = fs::temp_directory_path() / "nsf_test_contact_sheet";
  fs::remove_all(d);
  fs::create_directories(d);
  testing::write_synthetic_run((d / "a.h5").string(), 4);
  testing::write_synthetic_run((d / "b.h5").string(), 4);
  RunRenderOptions o;
  o.width = 100, o.height = 80;
  const Image sheet = contact_sheet({(d / "a.h5").string(), (d / "b.h5").string()}, 3, o);
  EXPECT_EQ(sheet.width, 3 * 100 + 2 * 8);
  // Each row: a caption band, then the panels.
  const int band = (sheet.height - 2 * 80 - 12) / 2;
  EXPECT_EQ(sheet.height, 2 * (band + 80) + 12);
  EXPECT_GE(band, text_height(caption_size(text_size_for(100, 80))));
  // The two panels of a row show different frames of a moving run.
  size_t differ = 0;
  for (int y = band; y < band + 80; ++y)
    for (int x = 0; x < 100; ++x) differ += sheet.at(x, y) != sheet.at(x + 216, y);
  EXPECT_GT(differ, 100u);
  // The captions hold text, and the two rows' captions differ (a.h5, b.h5).
  size_t ink = 0, captions_differ = 0;
  const int second = band + 80 + 12;
  for (int y = 0; y < band; ++y)
    for (int x = 0; x < sheet.width; ++x) {
      ink += sheet.at(x, y) != Rgb{255, 255, 255};
      captions_differ += sheet.at(x, y) != sheet.at(x, second + y);
    }
  EXPECT_GT(ink, 50u);
  EXPECT_GT(captions_differ, 10u);
  EXPECT_THROW(contact_sheet({(d / "missing.h5").string()}, 3, o), Error);
  fs::remove_all(d);
}

RunFacts facts(const std::string& file, std::optional<double> mu, bool rom = false) {
  RunFacts f;
  f.file = file;
  f.scene = "metal_small";
  f.rom = rom;
  f.split = rom ? "" : "test";
  f.parameter = "hardening";
  f.mu = mu;
  return f;
}

TEST(RunCaption, RowsOfOneSceneAreToldApart) {
  // Before, every row of a scene read just "METAL_SMALL".
  const std::vector<std::string> c =
      row_captions({facts("data/metal_small/test_0.h5", 0.05),
                    facts("data/metal_small/test_1.h5", 0.15), facts("out/rom.h5", 0.05, true)});
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c[0], "metal_small · μ = 0.05 (hardening) · simulation, test run · test_0.h5");
  EXPECT_EQ(c[1], "metal_small · μ = 0.15 (hardening) · simulation, test run · test_1.h5");
  EXPECT_EQ(c[2], "metal_small · μ = 0.05 (hardening) · reduced-order model · rom.h5");
}

TEST(RunCaption, FilesOfTheSameNameAreNamedByPath) {
  const std::vector<std::string> c =
      row_captions({facts("a/run.h5", std::nullopt), facts("b/run.h5", std::nullopt)});
  EXPECT_NE(c[0], c[1]);
  EXPECT_NE(c[0].find("a/run.h5"), std::string::npos) << c[0];
  EXPECT_EQ(c[0].find("μ"), std::string::npos) << "no sweep parameter, no μ: " << c[0];
}

TEST(RunCaption, FactsComeFromTheRunsAttributes) {
  const fs::path d = testing::fresh_dir("run_caption_facts");
  const std::string plain = (d / "plain.h5").string(), swept = (d / "swept.h5").string();
  testing::write_synthetic_run(plain, 1);
  {
    Particles ps = testing::synthetic_particles();
    SimSettings s;
    s.dx = 0.03125;
    RunWriter w(swept, ps, s, "two_blocks", testing::kSyntheticScene);
    w.set_attribute("rom", 1);
    w.set_attribute("mu", 2.5);
    w.set_attribute("sweep_parameter", "E");
    w.write_frame(ps, 0);
    w.finish();
  }
  const RunFacts p = run_facts(RunReader(plain)), q = run_facts(RunReader(swept));
  EXPECT_EQ(p.scene, "two_blocks");
  EXPECT_FALSE(p.rom);
  EXPECT_FALSE(p.mu.has_value());
  EXPECT_TRUE(q.rom);
  ASSERT_TRUE(q.mu.has_value());
  EXPECT_EQ(*q.mu, 2.5);
  EXPECT_EQ(q.parameter, "E");
  EXPECT_EQ(run_description(q), "two_blocks · μ = 2.5 (E)");
  fs::remove_all(d);
}

}  // namespace
}  // namespace nsf
