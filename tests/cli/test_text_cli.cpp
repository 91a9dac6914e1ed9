// `nsf render` without its font: a named error from a fresh process (the font is opened once per
// process), and nothing drawn. Text on pictures itself is unit/io/test_text.cpp's.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli_runner.h"
#include "synthetic_run.h"

namespace nsf {
namespace {

namespace fs = std::filesystem;

TEST(Text, AMissingFontFileIsANamedError) {
  // The font is opened once per process, so the check runs in a fresh nsf.
  const fs::path d = testing::fresh_dir("text_missing_font");
  const std::string run = (d / "run.h5").string(), out = (d / "frames").string();
  testing::write_synthetic_run(run, 2);
  std::string log;
  const int rc = testing::run_cli("render '" + run + "' -q --no-video --out '" + out + "'", log,
                                  "NSF_FONT=/nonexistent/font.ttf");
  EXPECT_NE(rc, 0);
  EXPECT_NE(log.find("NSF_FONT=/nonexistent/font.ttf"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(out)) << "nothing is drawn without a font";
  fs::remove_all(d);
}

}  // namespace
}  // namespace nsf
