// `nsf render` on a small hand-written run: pictures that show the particles and their motion,
// the video, the scene camera, frame ranges and legends, and clean failures for bad input.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "core/error.h"
#include "io/frame_range.h"
#include "io/image.h"
#include "io/legend.h"
#include "io/run_reader.h"
#include "io/run_render.h"
#include "mpm/scene/scene.h"
#include "synthetic_run.h"

namespace fs = std::filesystem;
using nsf::Image;
using nsf::testing::run_cli;

namespace {

int differing_pixels(const Image& a, const Image& b) {
  int n = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) n += a.at(x, y) != b.at(x, y);
  return n;
}

size_t distinct_colors(const Image& img) {
  std::set<uint32_t> seen;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const nsf::Rgb c = img.at(x, y);
      seen.insert(uint32_t(c.r) << 16 | uint32_t(c.g) << 8 | c.b);
    }
  return seen.size();
}

class RenderCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("nsf_render_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    run_ = (dir_ / "run.h5").string();
    nsf::testing::write_synthetic_run(run_, 3);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string render(const std::string& args, const std::string& env = "") {
    std::string out;
    EXPECT_EQ(run_cli("render '" + run_ + "' -q --size 200x150 " + args, out, env), 0) << out;
    return out;
  }

  fs::path dir_;
  std::string run_;
};

TEST_F(RenderCli, FramesShowTheParticlesAndTheirMotion) {
  const fs::path out = dir_ / "frames";
  render("--no-video --out '" + out.string() + "'");
  ASSERT_TRUE(fs::exists(out / "frame_0002.png"));
  EXPECT_FALSE(fs::exists(out / "frame_0003.png"));
  const Image first = nsf::read_png((out / "frame_0000.png").string());
  const Image last = nsf::read_png((out / "frame_0002.png").string());
  EXPECT_EQ(first.width, 200);
  EXPECT_EQ(first.height, 150);
  // Sky, ground, two shaded blocks, legend and label: far more than a blank picture's colours.
  EXPECT_GT(distinct_colors(first), 200u);
  // The blocks slide 0.08 m between them, a good fraction of the 0.7 m wide framing.
  EXPECT_GT(differing_pixels(first, last), 200 * 150 / 50);
  for (const auto& e : fs::directory_iterator(out)) EXPECT_EQ(e.path().extension(), ".png");
}

TEST_F(RenderCli, EveryColouringAndViewRenders) {
  for (const std::string color : {"material", "object", "speed", "stress"})
    for (const std::string view :
         {"--view front", "--view top", "--camera eye=2,1,2 target=0.5,0.2,0.5 fov=35"}) {
      const fs::path out = dir_ / (color + std::to_string(view.size()));
      render("--no-video --frames 1 --color " + color + " " + view + " --out '" + out.string() +
             "'");
      EXPECT_GT(distinct_colors(nsf::read_png((out / "frame_0000.png").string())), 100u)
          << color << " " << view;
    }
}

TEST_F(RenderCli, ParallelRenderingMatchesSerial) {
  const fs::path a = dir_ / "a", b = dir_ / "b";
  render("--no-video --color speed -j 1 --out '" + a.string() + "'");
  render("--no-video --color speed -j 2 --out '" + b.string() + "'");
  for (const char* name : {"frame_0000.png", "frame_0001.png", "frame_0002.png"})
    EXPECT_EQ(
        differing_pixels(nsf::read_png((a / name).string()), nsf::read_png((b / name).string())), 0)
        << name;
}

TEST_F(RenderCli, ColourScaleAndFloorAreFixedOverTheSelection) {
  const nsf::RunReader run(run_);
  nsf::RunRenderOptions o;
  o.color = nsf::ColorBy::Stress;
  const nsf::RenderPlan all = nsf::plan_render(run, {0, 1, 2}, o);
  double top = 0;
  for (size_t k : {0, 1, 2}) top = std::max(top, nsf::plan_render(run, {k}, o).hi);
  EXPECT_EQ(all.hi, top);  // the largest frame's scale, not the first frame's
  EXPECT_GT(all.hi, nsf::plan_render(run, {0}, o).hi);
  EXPECT_EQ(all.lo, 0);
  // The floor is the scene's plane collider at y = 0.1, not the lowest particle.
  EXPECT_DOUBLE_EQ(all.render.ground_height, 0.1);
  o.range_lo = 10, o.range_hi = 20;
  EXPECT_EQ(nsf::plan_render(run, {0}, o).hi, 20);
}

TEST_F(RenderCli, SceneCameraIsUsedAndCheckedByTheSceneLoader) {
  std::string scene = nsf::testing::kSyntheticScene;
  scene.insert(scene.rfind('}'),
               R"(, "camera": {"eye": [0.5, 0.3, 2.5], "target": [0.5, 0.2, 0.5], "fov_deg": 30})");
  nsf::testing::write_synthetic_run(run_, 2, scene);
  const fs::path with = dir_ / "with", without = dir_ / "without";
  render("--no-video --out '" + with.string() + "'");
  render("--no-video --view iso --out '" + without.string() + "'");
  EXPECT_GT(differing_pixels(nsf::read_png((with / "frame_0000.png").string()),
                             nsf::read_png((without / "frame_0000.png").string())),
            1000);
  // The scene loader accepts the key and rejects a malformed camera by name.
  auto j = nlohmann::json::parse(scene);
  EXPECT_TRUE(nsf::build_scene(j).camera.has_value());
  j["camera"]["fov_deg"] = 0;
  EXPECT_THROW(nsf::build_scene(j), nsf::Error);
  j["camera"] = {{"eye", {1, 1, 1}}, {"target", {1, 1, 1}}};
  EXPECT_THROW(nsf::build_scene(j), nsf::Error);
  j["camera"] = {{"eye", {1, 1, 1}}, {"target", {0, 0, 0}}, {"zoom", 2}};
  EXPECT_THROW(nsf::build_scene(j), nsf::Error);
}

// Mean x of the pixels where two pictures differ clearly (a collider, not the slightly
// different blur of the particles' shadows when a collider widens the shadow map).
double mean_x_of_difference(const Image& a, const Image& b) {
  double sum = 0;
  int n = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const nsf::Rgb p = a.at(x, y), q = b.at(x, y);
      if (std::abs(p.r - q.r) + std::abs(p.g - q.g) + std::abs(p.b - q.b) > 30) sum += x, ++n;
    }
  return n ? sum / n : -1;
}

TEST_F(RenderCli, CollidersAreDrawnAtEachFramesTimeUnlessTurnedOff) {
  // A box just over the blocks, moving 3 m/s along +x: 0.3 m between frames 0 and 2.
  std::string scene = nsf::testing::kSyntheticScene;
  scene.insert(scene.rfind(']'), R"(, {"type": "box", "center": [0.3, 0.36, 0.5],
      "size": [0.1, 0.1, 0.1], "motion": {"velocity": [3, 0, 0]}})");
  nsf::testing::write_synthetic_run(run_, 3, scene);
  const fs::path with = dir_ / "with", without = dir_ / "without";
  // One fixed camera for both, so that the pictures differ only by the box and its shadow.
  const std::string camera = "--camera eye=0.5,0.3,2.5 target=0.5,0.25,0.5 fov=35 ";
  render("--no-video " + camera + "--out '" + with.string() + "'");
  render("--no-video " + camera + "--no-colliders --out '" + without.string() + "'");
  const auto frame = [](const fs::path& dir, int k) {
    return nsf::read_png((dir / ("frame_000" + std::to_string(k) + ".png")).string());
  };
  EXPECT_GT(differing_pixels(frame(with, 0), frame(without, 0)), 200);
  // Seen from the front, the box's 0.3 m move is a good part of the picture's width (200 px).
  const double x0 = mean_x_of_difference(frame(with, 0), frame(without, 0));
  const double x2 = mean_x_of_difference(frame(with, 2), frame(without, 2));
  EXPECT_GT(x2, x0 + 20) << x0 << " -> " << x2;

  // The camera takes in the box, which flies above the blocks (0.12 to 0.28 m): the picture's
  // centre rises.
  const nsf::RunReader run(run_);
  nsf::RunRenderOptions o;
  o.view_dir = nsf::parse_view("front");
  const nsf::RenderPlan drawn = nsf::plan_render(run, {0, 1, 2}, o);
  o.colliders = false;
  const nsf::RenderPlan bare = nsf::plan_render(run, {0, 1, 2}, o);
  EXPECT_TRUE(bare.colliders.empty());
  EXPECT_GT(drawn.render.camera.target.y(), bare.render.camera.target.y() + 0.02);
}

TEST_F(RenderCli, AStoredColliderTheEngineRejectsFailsNamingIt) {
  std::string scene = nsf::testing::kSyntheticScene;
  scene.insert(scene.rfind(']'),
               R"(, {"type": "box", "center": [0.3, 0.5, 0.5], "size": [0.1, 0, 0.1]})");
  nsf::testing::write_synthetic_run(run_, 2, scene);
  const std::string out = (dir_ / "out").string();
  std::string output;
  EXPECT_NE(run_cli("render '" + run_ + "' -q --out '" + out + "'", output), 0);
  EXPECT_NE(output.find("colliders[1].size[1]"), std::string::npos) << output;
  EXPECT_NE(output.find("--no-colliders"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(out));
  render("--no-video --no-colliders --out '" + out + "'");
  EXPECT_TRUE(fs::exists(fs::path(out) / "frame_0001.png"));
}

TEST_F(RenderCli, MakesAVideoWithFfmpegAndSaysSoWithout) {
  const fs::path out = dir_ / "v";
  if (!nsf::testing::ffmpeg_available()) GTEST_SKIP() << "ffmpeg not installed";
  render("--out '" + out.string() + "'");
  ASSERT_TRUE(fs::exists(out / "run.mp4"));
  EXPECT_GT(fs::file_size(out / "run.mp4"), 1000u);
  render("--gif --out '" + out.string() + "'");
  ASSERT_TRUE(fs::exists(out / "run.gif"));
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_TRUE(e.path().extension() != ".tmp" && e.path().extension() != ".log") << e.path();

  const fs::path plain = dir_ / "plain";
  const std::string said = render("--out '" + plain.string() + "'", "PATH=/nonexistent");
  EXPECT_NE(said.find("ffmpeg is not on PATH"), std::string::npos) << said;
  EXPECT_TRUE(fs::exists(plain / "frame_0002.png"));
}

TEST_F(RenderCli, BadInputFailsClearlyAndWritesNothing) {
  const std::string out = (dir_ / "out").string();
  const fs::path corrupt = dir_ / "corrupt.h5";
  std::ofstream(corrupt) << "this is not an HDF5 file";
  struct Case {
    std::string args, expect;
  };
  const std::vector<Case> cases = {
      {"'" + (dir_ / "missing.h5").string() + "'", "missing.h5"},
      {"'" + corrupt.string() + "'", "corrupt.h5"},
      {"'" + run_ + "' --color rainbow", "--color"},
      {"'" + run_ + "' --frames 5", "--frames"},
      {"'" + run_ + "' --frames 2:1", "--frames"},
      {"'" + run_ + "' --frames 1:2:-1", "step"},
      {"'" + run_ + "' --view below", "--view"},
      {"'" + run_ + "' --camera eye=1,2", "--camera"},
      {"'" + run_ + "' --size 100", "--size"},
      {"'" + run_ + "' --range 3:1", "--range"},
  };
  for (const Case& c : cases) {
    std::string output;
    EXPECT_NE(run_cli("render " + c.args + " --out '" + out + "'", output), 0) << c.args;
    EXPECT_NE(output.find(c.expect), std::string::npos) << c.args << "\n" << output;
    EXPECT_FALSE(fs::exists(out)) << c.args;
  }
}

TEST(FrameRange, FollowsPythonSlices) {
  using V = std::vector<size_t>;
  EXPECT_EQ(nsf::parse_frame_range("", 4), (V{0, 1, 2, 3}));
  EXPECT_EQ(nsf::parse_frame_range(":", 4), (V{0, 1, 2, 3}));
  EXPECT_EQ(nsf::parse_frame_range("1:", 4), (V{1, 2, 3}));
  EXPECT_EQ(nsf::parse_frame_range("::2", 5), (V{0, 2, 4}));
  EXPECT_EQ(nsf::parse_frame_range("1:4:2", 5), (V{1, 3}));
  EXPECT_EQ(nsf::parse_frame_range("-1", 5), (V{4}));
  EXPECT_EQ(nsf::parse_frame_range("-2:", 5), (V{3, 4}));
  EXPECT_EQ(nsf::parse_frame_range(":-1", 3), (V{0, 1}));
  for (const char* bad : {"5", "-6", "3:2", "0:9", "::0", "a", "1:2:3:4", "1.5"})
    EXPECT_THROW(nsf::parse_frame_range(bad, 5), nsf::Error) << bad;
}

TEST(Legend, TicksAreRoundAndInsideTheRange) {
  const auto expect_ticks = [](double lo, double hi, std::vector<double> want) {
    const std::vector<double> got = nsf::nice_ticks(lo, hi);
    ASSERT_EQ(got.size(), want.size()) << lo << " " << hi;
    for (size_t i = 0; i < got.size(); ++i) EXPECT_NEAR(got[i], want[i], 1e-12);
  };
  expect_ticks(0, 1, {0, 0.2, 0.4, 0.6, 0.8, 1.0});
  expect_ticks(0, 2.7, {0, 0.5, 1, 1.5, 2, 2.5});
  expect_ticks(0.13, 0.61, {0.2, 0.3, 0.4, 0.5, 0.6});
  EXPECT_EQ(nsf::format_tick(0.5, 0.5), "0.5");
  EXPECT_EQ(nsf::format_tick(1500, 500), "1500");
  EXPECT_EQ(nsf::format_tick(0, 0.1), "0");
}

}  // namespace
