#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/colormap.h"
#include "io/image.h"
#include "io/png_render.h"
#include "io/text.h"

namespace fs = std::filesystem;
using nsf::Color;
using nsf::Image;
using nsf::Vec3;

namespace {

std::vector<Vec3> block(const Vec3& offset, int n = 8, double h = 0.05) {
  std::vector<Vec3> x;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) x.push_back(offset + h * Vec3(i, j, k));
  return x;
}

nsf::RenderOptions small_options() {
  nsf::RenderOptions opt;
  opt.width = 160;
  opt.height = 120;
  nsf::frame_box(opt, Vec3(0, 0, 0), Vec3(1, 1, 1));
  opt.radius = 0.03;
  return opt;
}

int differing_pixels(const Image& a, const Image& b) {
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  int n = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) n += a.at(x, y) != b.at(x, y);
  return n;
}

Image render(const std::vector<Vec3>& x, const nsf::RenderOptions& opt, Color c = Color(1, 0, 0)) {
  return nsf::render_particles(x, std::vector<Color>(x.size(), c), opt);
}

TEST(Render, ParticlesShowOverTheBackground) {
  const nsf::RenderOptions opt = small_options();
  const Image empty = render({}, opt);
  const Image full = render(block(Vec3(0.3, 0.3, 0.3)), opt);
  // The 0.4-wide block in a unit box framed to fill the picture covers a good part of it.
  EXPECT_GT(differing_pixels(empty, full), opt.width * opt.height / 20);
}

TEST(Render, MovedParticlesGiveADifferentPicture) {
  const nsf::RenderOptions opt = small_options();
  const Image a = render(block(Vec3(0.1, 0.3, 0.3)), opt);
  const Image b = render(block(Vec3(0.5, 0.3, 0.3)), opt);
  EXPECT_GT(differing_pixels(a, b), 200);
  EXPECT_EQ(differing_pixels(a, render(block(Vec3(0.1, 0.3, 0.3)), opt)), 0);  // deterministic
}

nsf::RenderOptions looking_down_z(double fov_deg) {
  nsf::RenderOptions opt;
  opt.width = opt.height = 64;
  opt.ground = false;
  opt.camera.eye = Vec3(0, 0, 5);
  opt.camera.target = Vec3(0, 0, 0);
  opt.camera.fov_deg = fov_deg;
  opt.camera.ortho_height = 2;
  opt.radius = 0.2;
  return opt;
}

TEST(Render, ParticleAtTargetIsDrawnAtTheCentre) {
  for (double fov : {0.0, 40.0}) {
    const nsf::RenderOptions opt = looking_down_z(fov);
    const Image img = render({Vec3(0, 0, 0)}, opt);
    const nsf::Rgb centre = img.at(32, 32);
    EXPECT_GT(centre.r, 100) << "fov " << fov;
    EXPECT_LT(centre.g, 80) << "fov " << fov;
    EXPECT_EQ(img.at(2, 32), render({}, opt).at(2, 32)) << "fov " << fov;
  }
}

TEST(Render, NearerParticleHidesTheFartherOne) {
  const nsf::RenderOptions opt = looking_down_z(0);
  const Vec3 near(0, 0, 1), far(0, 0, -1);
  const std::vector<Color> red_near_blue_far = {Color(1, 0, 0), Color(0, 0, 1)};
  for (bool near_first : {true, false}) {
    const std::vector<Vec3> x =
        near_first ? std::vector<Vec3>{near, far} : std::vector<Vec3>{far, near};
    std::vector<Color> c = red_near_blue_far;
    if (!near_first) std::swap(c[0], c[1]);
    const nsf::Rgb centre = nsf::render_particles(x, c, opt).at(32, 32);
    EXPECT_GT(centre.r, 100) << "near first: " << near_first;
    EXPECT_LT(centre.b, 30) << "near first: " << near_first;
  }
}

TEST(Render, FrameBoxKeepsEveryCornerInThePicture) {
  const Vec3 lo(-0.3, 0.1, 2.0), hi(1.7, 0.4, 2.5);
  std::vector<Vec3> corners;
  for (int c = 0; c < 8; ++c)
    corners.emplace_back(c & 1 ? hi.x() : lo.x(), c & 2 ? hi.y() : lo.y(), c & 4 ? hi.z() : lo.z());
  for (double fov : {0.0, 50.0}) {
    nsf::RenderOptions opt;
    opt.width = 120;
    opt.height = 90;
    opt.camera.fov_deg = fov;
    nsf::frame_box(opt, lo, hi);
    opt.ground = false;
    opt.radius = 1e-6;  // drawn at min_radius_px: a dot at each corner
    const Image empty = render({}, opt), dots = render(corners, opt);
    int inside = 0, on_border = 0;
    for (int y = 0; y < opt.height; ++y)
      for (int x = 0; x < opt.width; ++x) {
        if (empty.at(x, y) == dots.at(x, y)) continue;
        const bool border = x == 0 || y == 0 || x == opt.width - 1 || y == opt.height - 1;
        (border ? on_border : inside) += 1;
      }
    EXPECT_GE(inside, 8) << "fov " << fov;
    EXPECT_EQ(on_border, 0) << "fov " << fov;
  }
}

TEST(Render, RejectsAColourCountMismatch) {
  EXPECT_THROW(nsf::render_particles({Vec3(0, 0, 0)}, {}, small_options()), nsf::Error);
}

class PngFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("nsf_png_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(PngFile, WrittenPngReadsBackIdentical) {
  const Image img = render(block(Vec3(0.3, 0.3, 0.3)), small_options());
  const std::string path = (dir_ / "frame.png").string();
  nsf::write_png(img, path);
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  const Image back = nsf::read_png(path);
  EXPECT_EQ(back.width, 160);
  EXPECT_EQ(back.height, 120);
  EXPECT_EQ(back.rgb, img.rgb);
}

TEST_F(PngFile, UnreadablePngNamesTheFile) {
  const std::string missing = (dir_ / "missing.png").string();
  const std::string junk = (dir_ / "junk.png").string();
  std::ofstream(junk) << "not a png at all";
  for (const std::string& path : {missing, junk}) {
    try {
      nsf::read_png(path);
      ADD_FAILURE() << path << " read without error";
    } catch (const nsf::Error& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
}

TEST_F(PngFile, WriteToAMissingDirectoryFailsNamingTheFile) {
  const std::string path = (dir_ / "no" / "frame.png").string();
  try {
    nsf::write_png(Image(4, 4), path);
    FAIL() << "no error";
  } catch (const nsf::Error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST(Image, SideBySidePlacesBothAndPadsTheShorter) {
  const Image a(3, 2, {10, 0, 0}), b(4, 5, {0, 20, 0});
  const Image s = nsf::side_by_side(a, b, 2, {1, 2, 3});
  ASSERT_EQ(s.width, 9);
  ASSERT_EQ(s.height, 5);
  EXPECT_EQ(s.at(2, 1), (nsf::Rgb{10, 0, 0}));
  EXPECT_EQ(s.at(2, 4), (nsf::Rgb{1, 2, 3}));  // below a
  EXPECT_EQ(s.at(4, 0), (nsf::Rgb{1, 2, 3}));  // the gap
  EXPECT_EQ(s.at(5, 4), (nsf::Rgb{0, 20, 0}));
}

TEST(Image, TextDrawsInsideItsBoxOnly) {
  Image img(100, 40, {255, 255, 255});
  nsf::draw_text(img, 5, 6, "ROM 1.5", {0, 0, 0}, 20);
  const int w = nsf::text_width("ROM 1.5", 20), h = nsf::text_height(20);
  int inside = 0, outside = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      if (img.at(x, y) == nsf::Rgb{255, 255, 255}) continue;
      (x >= 5 && x < 5 + w && y >= 6 && y < 6 + h ? inside : outside) += 1;
    }
  EXPECT_GT(inside, 50);
  EXPECT_EQ(outside, 0);
}

TEST(Colormap, ViridisGetsBrighterAndScalarsUseTheirRange) {
  const auto luma = [](const Color& c) { return 0.3f * c.x() + 0.59f * c.y() + 0.11f * c.z(); };
  for (int i = 0; i < 20; ++i)
    EXPECT_LT(luma(nsf::viridis(i / 20.0)), luma(nsf::viridis((i + 1) / 20.0)));
  const std::vector<Color> c = nsf::colors_by_scalar({5.0, 7.0, 6.0});
  EXPECT_TRUE(c[0].isApprox(nsf::viridis(0)));
  EXPECT_TRUE(c[1].isApprox(nsf::viridis(1)));
  EXPECT_TRUE(c[2].isApprox(nsf::viridis(0.5)));
  EXPECT_FALSE(nsf::palette(0).isApprox(nsf::palette(1)));
}

TEST(Colormap, VonMisesIgnoresPressure) {
  EXPECT_NEAR(nsf::von_mises(-3.0 * nsf::Mat3::Identity()), 0.0, 1e-12);
  nsf::Mat3 uniaxial = nsf::Mat3::Zero();
  uniaxial(0, 0) = 2.5;
  EXPECT_NEAR(nsf::von_mises(uniaxial), 2.5, 1e-12);
}

}  // namespace
