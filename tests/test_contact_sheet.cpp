#include <gtest/gtest.h>

#include <filesystem>

#include "core/error.h"
#include "io/contact_sheet.h"
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
  EXPECT_EQ(sheet.height, 2 * 80 + 12);
  // The two panels of a row show different frames of a moving run.
  size_t differ = 0;
  for (int y = 0; y < 80; ++y)
    for (int x = 0; x < 100; ++x) differ += sheet.at(x, y) != sheet.at(x + 216, y);
  EXPECT_GT(differ, 100u);
  EXPECT_THROW(contact_sheet({(d / "missing.h5").string()}, 3, o), Error);
  fs::remove_all(d);
}

}  // namespace
}  // namespace nsf
