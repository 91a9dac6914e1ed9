// The loss-curve picture: scene names and --out paths reach gnuplot as data, never as program
// text. Before, `nsf train` of a dataset whose scene is named  x'; system "touch PWNED"; #  (or
// with --out "m';touch PWNED;'.nsf") ran `touch PWNED`.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "core/process.h"
#include "nn/train/loss_plot.h"

namespace {

namespace fs = std::filesystem;

void write_loss_csv(const fs::path& p) {
  std::ofstream csv(p);
  csv << "stage,network,step,loss,loss_smooth,lr\n";
  for (int stage = 1; stage <= 3; ++stage)
    for (int step = 1; step <= 20; ++step)
      csv << stage << ",g," << step << "," << 1.0 / step << "," << 1.0 / step << ",0.001\n";
}

class LossPlot : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!nsf::program_exists("gnuplot")) GTEST_SKIP() << "gnuplot not installed";
    old_ = fs::current_path();
    dir_ = nsf::testing::fresh_dir("loss_plot");
    // A relative `touch PWNED` lands in the working directory: make that one we look into.
    fs::current_path(dir_);
  }
  void TearDown() override {
    if (old_.empty()) return;
    fs::current_path(old_);
    fs::remove_all(dir_);
  }
  bool pwned() const { return fs::exists(dir_ / "PWNED") || fs::exists(old_ / "PWNED"); }
  fs::path old_, dir_;
};

TEST_F(LossPlot, HostileTitlesAreOnlyText) {
  write_loss_csv(dir_ / "m.loss.csv");
  const std::string abs = (dir_ / "PWNED").string();
  const std::vector<std::string> titles = {
      "nsf train: x'; system \"touch PWNED\"; #", "nsf train: x\"; system \"touch PWNED\"; #",
      "x'\nsystem \"touch " + abs + "\"\n#",      "$(touch PWNED) `touch PWNED` ; touch PWNED",
      "x' . system(\"touch " + abs + "\") . '",   "@ARG1 @ARG3 {/Symbol a} \\",
  };
  for (const std::string& title : titles) {
    const fs::path png = dir_ / "m.loss.png";
    fs::remove(png);
    EXPECT_EQ(nsf::plot_loss_curves((dir_ / "m.loss.csv").string(), png.string(), title), "")
        << title;
    EXPECT_GT(fs::file_size(png), 1000u) << title;
    EXPECT_FALSE(pwned()) << title;
  }
}

TEST_F(LossPlot, HostilePathsAreOnlyFileNames) {
  // Relative names on purpose: gnuplot runs '<cmd' as a data file and '|cmd' as an output.
  const std::vector<std::string> stems = {
      "m';touch PWNED;'", "m\";touch PWNED;\"",           "<touch PWNED",
      "|touch PWNED",     "$(touch PWNED);`touch PWNED`", "a\nb'; system \"touch PWNED\"; #",
  };
  for (const std::string& stem : stems) {
    const std::string csv = stem + ".loss.csv", png = stem + ".loss.png";
    write_loss_csv(dir_ / csv);
    EXPECT_EQ(nsf::plot_loss_curves(csv, png, "nsf train: " + stem), "") << stem;
    EXPECT_TRUE(fs::exists(dir_ / png)) << stem;
    EXPECT_FALSE(fs::exists(dir_ / (png + ".tmp"))) << stem;
    EXPECT_FALSE(pwned()) << stem;
  }
}

TEST_F(LossPlot, SaysWhyWhenThereIsNoPicture) {
  // A CSV that is not there: gnuplot fails, nothing is left half-written, and the note says so.
  const std::string why = nsf::plot_loss_curves("missing.csv", "missing.png", "t");
  EXPECT_NE(why.find("gnuplot failed"), std::string::npos) << why;
  EXPECT_FALSE(fs::exists(dir_ / "missing.png"));
  EXPECT_FALSE(fs::exists(dir_ / "missing.png.tmp"));
}

}  // namespace
