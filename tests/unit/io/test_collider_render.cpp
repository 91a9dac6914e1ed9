// Colliders in pictures: rebuilt from a run's scene JSON at a frame's time, drawn where they are,
// behind nearer particles and over farther ones, with a shadow, and the floor plane not twice.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "error_matchers.h"
#include "io/collider_shapes.h"
#include "io/png_render.h"
#include "io/render_view.h"

using nsf::ColliderShape;
using nsf::Color;
using nsf::Image;
using nsf::Vec3;
using Kind = nsf::ColliderShape::Kind;

namespace {

constexpr const char* kScene = R"({
  "name": "three_colliders",
  "colliders": [
    {"type": "box", "center": [0.5, 0.5, 0.5], "size": [0.2, 0.1, 0.4], "rotate_deg": [0, 0, 30],
     "motion": {"velocity": [1, 0, 0], "end": 0.5}},
    {"type": "cylinder", "center": [0.2, 0.3, 0.5], "radius": 0.05, "height": 0.3, "axis": "z"},
    {"type": "plane", "point": [0, 0.1, 0], "normal": [0, 2, 0], "contact": "sticky"}
  ]
})";

TEST(ColliderShapes, AreTheScenesCollidersAtTheFramesTime) {
  const nsf::SceneColliders colliders = nsf::SceneColliders::from_scene_json(kScene);
  const std::vector<ColliderShape> at0 = colliders.at(0.0), at1 = colliders.at(1.0);
  ASSERT_EQ(at0.size(), 3u);
  EXPECT_EQ(at0[0].kind, Kind::Box);
  EXPECT_TRUE(at0[0].half.isApprox(Vec3(0.1, 0.05, 0.2)));
  EXPECT_NEAR(at0[0].rotation(1, 0), std::sin(30 * M_PI / 180), 1e-12);  // turned about z
  EXPECT_TRUE(at0[0].center.isApprox(Vec3(0.5, 0.5, 0.5)));
  // The scripted motion: 1 m/s along x until t = 0.5, then at rest.
  EXPECT_TRUE(at1[0].center.isApprox(Vec3(1.0, 0.5, 0.5)));
  EXPECT_EQ(at0[1].kind, Kind::Cylinder);
  EXPECT_DOUBLE_EQ(at0[1].radius, 0.05);
  EXPECT_DOUBLE_EQ(at0[1].height, 0.3);
  EXPECT_EQ(at0[1].axis, 2);
  EXPECT_EQ(at0[2].kind, Kind::Plane);
  EXPECT_TRUE(at0[2].normal.isApprox(Vec3(0, 1, 0)));  // normalised like the engine's
  EXPECT_DOUBLE_EQ(at0[2].center.y(), 0.1);
}

TEST(ColliderShapes, ScenesWithoutCollidersOrReadableJsonHaveNone) {
  EXPECT_TRUE(nsf::SceneColliders::from_scene_json(R"({"name": "x"})").empty());
  EXPECT_TRUE(nsf::SceneColliders::from_scene_json("not json").empty());
  EXPECT_TRUE(nsf::SceneColliders::from_scene_json("").empty());
  EXPECT_TRUE(nsf::SceneColliders().at(0.3).empty());
}

TEST(ColliderShapes, AColliderTheEngineRejectsFailsNamingIt) {
  const std::string bad = R"({"colliders": [
    {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]},
    {"type": "box", "center": [0, 0, 0], "size": [0.1, -1, 0.1]}]})";
  const std::string msg =
      nsf::testing::error_of([&] { nsf::SceneColliders::from_scene_json(bad); });
  nsf::testing::expect_contains(msg, "colliders[1].size[1]");
  nsf::testing::expect_contains(msg, "run's colliders");
  nsf::testing::expect_contains(
      nsf::testing::error_of([] { nsf::SceneColliders::from_scene_json(R"({"colliders": 3})"); }),
      "must be an array");
}

TEST(ColliderShapes, BoundsCoverTheTurnedShape) {
  ColliderShape box;
  box.kind = Kind::Box;
  box.center = Vec3(1, 2, 3);
  box.half = Vec3(0.5, 0.1, 0.2);
  box.rotation = Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()).toRotationMatrix();
  Vec3 lo, hi;
  ASSERT_TRUE(nsf::bounds(box, lo, hi));
  EXPECT_TRUE(lo.isApprox(Vec3(0.9, 1.5, 2.8)));  // x and y extents swapped by the quarter turn
  EXPECT_TRUE(hi.isApprox(Vec3(1.1, 2.5, 3.2)));
  ColliderShape plane;
  plane.kind = Kind::Plane;
  EXPECT_FALSE(nsf::bounds(plane, lo, hi));
}

// A unit-box scene seen from the default three-quarter view, ground at y = 0.
nsf::RenderOptions options() {
  nsf::RenderOptions opt;
  opt.width = 160;
  opt.height = 120;
  nsf::frame_box(opt, Vec3(0, 0, 0), Vec3(1, 1, 1));
  opt.radius = 0.03;
  return opt;
}

ColliderShape box_at(const Vec3& c, double half) {
  ColliderShape s;
  s.kind = Kind::Box;
  s.center = c;
  s.half = Vec3::Constant(half);
  return s;
}

// Pixel of a world point in a picture rendered with `opt`.
void pixel_of(const nsf::RenderOptions& opt, const Vec3& p, int& px, int& py) {
  const nsf::View view(opt.camera, opt.width, opt.height);
  double sx, sy, depth;
  ASSERT_TRUE(view.project(p, sx, sy, depth));
  px = static_cast<int>(sx), py = static_cast<int>(sy);
  ASSERT_TRUE(px >= 0 && py >= 0 && px < opt.width && py < opt.height);
}

Image render(const std::vector<Vec3>& x, const nsf::RenderOptions& opt) {
  return nsf::render_particles(x, std::vector<Color>(x.size(), Color(1, 0, 0)), opt);
}

bool same(const nsf::Rgb& a, const nsf::Rgb& b) {
  return a == b;
}

TEST(ColliderDrawing, ABoxShowsWhereItIsAndNowhereElse) {
  nsf::RenderOptions opt = options();
  const Image without = render({}, opt);
  opt.colliders = {box_at(Vec3(0.5, 0.5, 0.5), 0.1)};
  const Image with = render({}, opt);
  int cx, cy;
  pixel_of(opt, Vec3(0.5, 0.5, 0.5), cx, cy);
  EXPECT_FALSE(same(with.at(cx, cy), without.at(cx, cy)));
  // The picture's corners are sky or ground far from the box (and its shadow below it).
  EXPECT_TRUE(same(with.at(2, 2), without.at(2, 2)));
  EXPECT_TRUE(same(with.at(opt.width - 3, 2), without.at(opt.width - 3, 2)));
  // Steel grey, not the red particle colour nor a sky blue: about as much red as blue.
  const nsf::Rgb c = with.at(cx, cy);
  EXPECT_LT(std::abs(int(c.r) - int(c.b)), 40);
}

TEST(ColliderDrawing, NearerParticlesStayOnTopAndFartherOnesShowThroughTinted) {
  nsf::RenderOptions opt = options();
  const Vec3 box(0.5, 0.5, 0.5);
  const Vec3 towards_eye = (opt.camera.eye - box).normalized();
  const std::vector<Vec3> front = {box + 0.3 * towards_eye}, behind = {box - 0.3 * towards_eye};
  int cx, cy;
  pixel_of(opt, box, cx, cy);  // both particles and the box lie on this pixel's ray
  const Image front_alone = render(front, opt), behind_alone = render(behind, opt);
  opt.colliders = {box_at(box, 0.1)};
  const Image front_with = render(front, opt), behind_with = render(behind, opt);
  EXPECT_TRUE(same(front_with.at(cx, cy), front_alone.at(cx, cy)));
  const nsf::Rgb b0 = behind_alone.at(cx, cy), b1 = behind_with.at(cx, cy);
  EXPECT_FALSE(same(b0, b1));
  EXPECT_GT(b0.r, 100);  // a red particle alone
  EXPECT_GT(b1.r, b1.b + 20) << "still reddish through the translucent box";
  EXPECT_LT(b1.r, b0.r);
}

TEST(ColliderDrawing, CylindersAndInclinedPlanesAreDrawnTheFloorPlaneIsNot) {
  nsf::RenderOptions opt = options();
  const Image without = render({}, opt);

  ColliderShape cylinder;
  cylinder.kind = Kind::Cylinder;
  cylinder.center = Vec3(0.5, 0.5, 0.5);
  cylinder.radius = 0.1;
  cylinder.height = 0.6;
  cylinder.axis = 2;
  opt.colliders = {cylinder};
  int cx, cy;
  pixel_of(opt, cylinder.center, cx, cy);
  EXPECT_FALSE(same(render({}, opt).at(cx, cy), without.at(cx, cy)));

  ColliderShape floor;
  floor.kind = Kind::Plane;
  floor.center = Vec3(0, opt.ground_height, 0);
  floor.normal = Vec3::UnitY();
  opt.colliders = {floor};
  const Image with_floor = render({}, opt);
  for (int y = 0; y < opt.height; y += 7)
    for (int x = 0; x < opt.width; x += 7)
      EXPECT_TRUE(same(with_floor.at(x, y), without.at(x, y))) << x << "," << y;

  ColliderShape ramp = floor;
  ramp.center = Vec3(0.5, 0.3, 0.5);
  ramp.normal = Vec3(-0.5, 1, 0).normalized();
  opt.colliders = {ramp};
  int rx, ry;
  pixel_of(opt, ramp.center, rx, ry);
  EXPECT_FALSE(same(render({}, opt).at(rx, ry), without.at(rx, ry)));
}

TEST(ColliderDrawing, ABoxAboveTheGroundCastsAShadowUnderIt) {
  nsf::RenderOptions opt = options();
  const Vec3 centre(0.5, 0.8, 0.5);
  int sx, sy;
  pixel_of(opt, Vec3(centre.x(), opt.ground_height, centre.z()), sx, sy);
  const nsf::Rgb bare = render({}, opt).at(sx, sy);
  opt.colliders = {box_at(centre, 0.1)};
  const nsf::Rgb shaded = render({}, opt).at(sx, sy);
  EXPECT_LT(shaded.r + shaded.g + shaded.b, bare.r + bare.g + bare.b - 30);
}

TEST(ColliderDrawing, TheGroundHidesWhatIsBelowIt) {
  nsf::RenderOptions opt = options();
  const Image without = render({}, opt);
  opt.colliders = {box_at(Vec3(0.5, opt.ground_height - 0.3, 0.5), 0.1)};
  opt.shadows = false;
  const Image buried = render({}, opt);
  for (int y = 0; y < opt.height; y += 3)
    for (int x = 0; x < opt.width; x += 3)
      EXPECT_TRUE(same(buried.at(x, y), without.at(x, y))) << x << "," << y;
}

}  // namespace
