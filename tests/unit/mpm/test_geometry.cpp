// Shapes, CSG, transforms and particle sampling (src/mpm/scene/geometry, shape_json, sampling).
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/rotation.h"
#include "core/sdf.h"
#include "mpm/scene/sampling.h"
#include "mpm/scene/shape_json.h"

namespace nsf {
namespace {

using nlohmann::json;

// Unit domain, dx = 1/64, 2x2x2 particles per cell.
Lattice unit_lattice(int ppc = 2, double dx = 1.0 / 64) {
  return {Vec3::Zero(), Vec3::Ones(), dx, ppc};
}

ShapePtr shape(const char* text) {
  return parse_shape(json::parse(text), "shape");
}

size_t count(const Shape& s, const Lattice& L = unit_lattice()) {
  return sample_shape(s, L).size();
}

double sampled_volume(const Shape& s, const Lattice& L = unit_lattice()) {
  return count(s, L) * L.particle_volume();
}

TEST(Sampling, CellAlignedBoxHasExactCount) {
  // 16 x 8 x 4 cells.
  auto box = make_box(Vec3(0.25, 0.25, 0.25), Vec3(0.5, 0.375, 0.3125));
  EXPECT_EQ(count(*box), 32u * 16u * 8u);
  EXPECT_EQ(count(*box, unit_lattice(3)), 48u * 24u * 12u);
  EXPECT_EQ(count(*box, unit_lattice(1)), 16u * 8u * 4u);
}

TEST(Sampling, UnalignedBoxOfWholeCellsStillHasExactCount) {
  // 10 cells wide but shifted by 0.3 cell: no lattice point falls on a face.
  const double dx = 1.0 / 64;
  Vec3 lo = Vec3::Constant(0.3 + 0.3 * dx);
  auto box = make_box(lo, lo + Vec3::Constant(10 * dx));
  EXPECT_EQ(count(*box), 20u * 20u * 20u);
}

TEST(Sampling, PositionsAreCellCentredSubCellOffsetsInDeterministicOrder) {
  const double dx = 1.0 / 64, h = dx / 2;
  auto box = make_box(Vec3(0.25, 0.25, 0.25), Vec3(0.25 + 2 * dx, 0.25 + dx, 0.25 + dx));
  std::vector<Vec3> p = sample_shape(*box, unit_lattice());
  ASSERT_EQ(p.size(), 4u * 2u * 2u);
  EXPECT_TRUE(p[0].isApprox(Vec3(0.25 + 0.5 * h, 0.25 + 0.5 * h, 0.25 + 0.5 * h)));
  // z varies fastest, then y, then x.
  EXPECT_TRUE(p[1].isApprox(p[0] + Vec3(0, 0, h)));
  EXPECT_TRUE(p[2].isApprox(p[0] + Vec3(0, h, 0)));
  EXPECT_TRUE(p[4].isApprox(p[0] + Vec3(h, 0, 0)));
  EXPECT_EQ(sample_shape(*box, unit_lattice()), p);
}

TEST(Sampling, ClipsAtTheDomainFaces) {
  auto box = make_box(Vec3(-1, -1, -1), Vec3(2, 2, 2));
  EXPECT_EQ(count(*box, unit_lattice(1, 0.125)), 8u * 8u * 8u);
}

TEST(Sampling, SphereVolumeIsCloseToAnalytic) {
  const double r = 0.15;
  auto s = make_sphere(Vec3(0.5, 0.5, 0.5), r);
  EXPECT_NEAR(sampled_volume(*s) / (4.0 / 3.0 * M_PI * r * r * r), 1.0, 0.02);
}

TEST(Sampling, CylinderCapsuleTorusVolumesAreCloseToAnalytic) {
  auto cyl = make_cylinder(Vec3(0.5, 0.5, 0.5), 0.12, 0.3, 0);
  EXPECT_NEAR(sampled_volume(*cyl) / (M_PI * 0.12 * 0.12 * 0.3), 1.0, 0.03);
  auto cap = make_capsule(Vec3(0.3, 0.5, 0.5), Vec3(0.7, 0.5, 0.5), 0.08);
  double cap_v = M_PI * 0.08 * 0.08 * 0.4 + 4.0 / 3.0 * M_PI * std::pow(0.08, 3);
  EXPECT_NEAR(sampled_volume(*cap) / cap_v, 1.0, 0.03);
  auto tor = make_torus(Vec3(0.5, 0.5, 0.5), 0.2, 0.06, 2);
  EXPECT_NEAR(sampled_volume(*tor) / (2 * M_PI * M_PI * 0.2 * 0.06 * 0.06), 1.0, 0.03);
  // A z-axis torus lies in the xy plane.
  EXPECT_TRUE(tor->contains(Vec3(0.7, 0.5, 0.5)));
  EXPECT_TRUE(tor->contains(Vec3(0.5, 0.7, 0.5)));
  EXPECT_FALSE(tor->contains(Vec3(0.5, 0.5, 0.7)));
}

TEST(Csg, DifferenceRemovesTheSecondShape) {
  auto d = shape(R"({"type": "difference", "children": [
      {"type": "box", "center": [0.5, 0.5, 0.5], "size": [0.4, 0.4, 0.4]},
      {"type": "sphere", "center": [0.5, 0.5, 0.5], "radius": 0.15}]})");
  EXPECT_FALSE(d->contains(Vec3(0.5, 0.5, 0.5)));
  EXPECT_TRUE(d->contains(Vec3(0.32, 0.32, 0.32)));
  auto box = shape(R"({"type": "box", "center": [0.5, 0.5, 0.5], "size": [0.4, 0.4, 0.4]})");
  auto ball = make_sphere(Vec3(0.5, 0.5, 0.5), 0.15);
  EXPECT_EQ(count(*d) + count(*ball), count(*box));  // the ball lies inside the box
}

TEST(Csg, UnionAndIntersectionCountsAreConsistent) {
  const char* a = R"({"type": "sphere", "center": [0.45, 0.5, 0.5], "radius": 0.12})";
  const char* b = R"({"type": "sphere", "center": [0.6, 0.5, 0.5], "radius": 0.12})";
  auto u = shape((std::string(R"({"type": "union", "children": [)") + a + "," + b + "]}").c_str());
  auto i = shape(
      (std::string(R"({"type": "intersection", "children": [)") + a + "," + b + "]}").c_str());
  size_t na = count(*shape(a)), nb = count(*shape(b)), nu = count(*u), ni = count(*i);
  EXPECT_GT(ni, 0u);
  EXPECT_EQ(nu + ni, na + nb);
  EXPECT_LT(nu, na + nb);
}

TEST(Transform, TranslateMovesTheShape) {
  auto s = shape(R"({"type": "sphere", "center": [0, 0, 0], "radius": 0.1,
                     "transform": {"translate": [0.5, 0.4, 0.3]}})");
  EXPECT_NEAR(s->sdf(Vec3(0.5, 0.4, 0.3)), -0.1, 1e-12);
  EXPECT_NEAR(s->sdf(Vec3(0.7, 0.4, 0.3)), 0.1, 1e-12);
}

TEST(Transform, RotateTurnsALongBoxUpright) {
  auto s = shape(R"({"type": "box", "center": [0, 0, 0], "size": [0.4, 0.1, 0.1],
                     "transform": {"rotate_deg": [0, 0, 90], "translate": [0.5, 0.5, 0.5]}})");
  EXPECT_TRUE(s->contains(Vec3(0.5, 0.68, 0.5)));
  EXPECT_FALSE(s->contains(Vec3(0.68, 0.5, 0.5)));
  Aabb b = s->bounds();
  EXPECT_NEAR(b.hi.y() - b.lo.y(), 0.4, 1e-12);
  EXPECT_NEAR(b.hi.x() - b.lo.x(), 0.1, 1e-12);
}

TEST(Transform, ScaleUniformAndPerAxis) {
  auto s = shape(R"({"type": "sphere", "center": [0, 0, 0], "radius": 0.1,
                     "transform": {"scale": 2}})");
  EXPECT_NEAR(s->sdf(Vec3(0.3, 0, 0)), 0.1, 1e-12);
  auto e = shape(R"({"type": "sphere", "center": [0, 0, 0], "radius": 0.1,
                     "transform": {"scale": [2, 1, 1]}})");
  EXPECT_TRUE(e->contains(Vec3(0.19, 0, 0)));
  EXPECT_FALSE(e->contains(Vec3(0, 0.11, 0)));
}

TEST(Transform, OnACombinatorAppliesToTheWholeTree) {
  auto s = shape(R"({"type": "union", "transform": {"translate": [0.5, 0, 0]},
                     "children": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.05},
                                  {"type": "sphere", "center": [0, 0.2, 0], "radius": 0.05}]})");
  EXPECT_TRUE(s->contains(Vec3(0.5, 0, 0)));
  EXPECT_TRUE(s->contains(Vec3(0.5, 0.2, 0)));
  EXPECT_FALSE(s->contains(Vec3(0, 0, 0)));
}

TEST(Rotation, EulerDegreesAreExtrinsicXThenYThenZ) {
  // x first maps y to z, then y maps z to x. The opposite order would map y to z.
  Vec3 r = rotation_from_euler_deg(Vec3(90, 90, 0)) * Vec3::UnitY();
  EXPECT_TRUE(r.isApprox(Vec3::UnitX(), 1e-12)) << r.transpose();
}

TEST(Sdf, BoxAndCylinderNormalsPointOutOfTheNearestFace) {
  Vec3 half(0.5, 0.2, 0.3);
  EXPECT_TRUE(sdf::box_normal(Vec3(0.45, 0.0, 0.0), half).isApprox(Vec3::UnitX()));
  EXPECT_TRUE(sdf::box_normal(Vec3(0.0, -0.15, 0.1), half).isApprox(-Vec3::UnitY()));
  EXPECT_NEAR(sdf::box(Vec3(0.0, -0.15, 0.1), half), -0.05, 1e-12);
  EXPECT_TRUE(sdf::cylinder_normal(Vec3(0.0, 0.0, 0.09), 0.1, 1.0, 1).isApprox(Vec3::UnitZ()));
  EXPECT_TRUE(sdf::cylinder_normal(Vec3(0.0, 0.48, 0.0), 0.1, 1.0, 1).isApprox(Vec3::UnitY()));
}

TEST(ShapeJson, RejectsBadShapesNamingTheKey) {
  auto expect_error = [](const char* text, const std::string& needle) {
    try {
      parse_shape(json::parse(text), "objects[0].shape");
      ADD_FAILURE() << "accepted " << text;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect_error(R"({"type": "cube"})", "objects[0].shape.type");
  expect_error(R"({"type": "sphere", "center": [0, 0, 0], "radius": -1})",
               "objects[0].shape.radius");
  expect_error(R"({"type": "sphere", "center": [0, 0], "radius": 1})", "objects[0].shape.center");
  expect_error(R"({"type": "box", "min": [0, 0, 0], "max": [1, 1, 1], "size": [1, 1, 1]})",
               "objects[0].shape");
  expect_error(R"({"type": "box", "min": [0, 0, 0], "max": [1, 0, 1]})", "objects[0].shape.max");
  expect_error(
      R"({"type": "cylinder", "center": [0, 0, 0], "radius": 1, "height": 1, "axis": "w"})",
      "objects[0].shape.axis");
  expect_error(
      R"({"type": "difference", "children": [{"type": "sphere", "center": [0, 0, 0], "radius": 1}]})",
      "objects[0].shape.children");
  expect_error(
      R"({"type": "union", "children": [{"type": "sphere", "center": [0, 0, 0], "radius": 0}]})",
      "objects[0].shape.children[0].radius");
  expect_error(
      R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "transform": {"rotate": [0, 0, 1]}})",
      "objects[0].shape.transform.rotate");
  expect_error(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "transform": {"scale": 0}})",
               "objects[0].shape.transform.scale");
}

}  // namespace
}  // namespace nsf
