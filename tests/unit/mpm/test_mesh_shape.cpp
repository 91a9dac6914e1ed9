// Mesh shapes (src/mpm/scene/mesh): OBJ/STL input, winding-number inside test, orientation
// repair, hole tolerance, path resolution and errors. Meshes are generated and written here.
#include <gtest/gtest.h>

#include "error_matchers.h"

#include <cmath>
#include <fstream>
#include <random>
#include <string>

#include "core/error.h"
#include "mesh_fixtures.h"
#include "mpm/scene/mesh/mesh_shape.h"
#include "mpm/scene/mesh/orientation.h"
#include "mpm/scene/mesh/winding_bvh.h"
#include "mpm/scene/sampling.h"
#include "mpm/scene/scene.h"

namespace nsf {
namespace {

using nlohmann::json;
using testing::TempDir;

// dx = 1/32, ppc 2: a cell-aligned 8-cell box [0.25, 0.5]³ holds (8·2)³ = 4096 particles.
json scene_with_shape(const json& shape) {
  return json{
      {"simulation", {{"dx", 1.0 / 32}, {"dt", 1e-4}, {"ppc", 2}}},
      {"objects",
       {{{"shape", shape}, {"material", {{"type", "fixed_corotated"}, {"E", 1e4}, {"nu", 0.3}}}}}}};
}

// The unit-cube mesh in `file`, scaled and moved onto the box [0.25, 0.5]³.
json cube_shape(const std::string& file) {
  return json{{"type", "mesh"},
              {"file", file},
              {"scale", 0.25},
              {"transform", {{"translate", {0.25, 0.25, 0.25}}}}};
}

size_t particle_count(const json& shape) {
  return build_scene(scene_with_shape(shape)).particles.size();
}

const size_t kBoxCount = 4096;

TEST(MeshShape, ClosedCubeGivesExactlyTheBoxParticles) {
  TempDir dir("mesh_cube");
  testing::write_obj(testing::unit_cube(), dir.file("cube.obj"));
  Scene mesh = build_scene(scene_with_shape(cube_shape(dir.file("cube.obj"))));
  Scene box = build_scene(scene_with_shape(
      json{{"type", "box"}, {"min", {0.25, 0.25, 0.25}}, {"max", {0.5, 0.5, 0.5}}}));
  ASSERT_EQ(box.particles.size(), kBoxCount);
  ASSERT_EQ(mesh.particles.size(), kBoxCount);
  for (size_t p = 0; p < kBoxCount; ++p) EXPECT_EQ(mesh.particles.X[p], box.particles.X[p]);
}

TEST(MeshShape, BinaryAndAsciiStlBothLoad) {
  TempDir dir("mesh_stl");
  testing::write_binary_stl(testing::unit_cube(), dir.file("binary.stl"));
  testing::write_ascii_stl(testing::unit_cube(), dir.file("ascii.stl"));
  EXPECT_EQ(particle_count(cube_shape(dir.file("binary.stl"))), kBoxCount);
  EXPECT_EQ(particle_count(cube_shape(dir.file("ascii.stl"))), kBoxCount);
}

TEST(MeshShape, SphereVolumeMatches) {
  TempDir dir("mesh_sphere");
  const double r = 0.2;
  TriangleMesh sphere = testing::icosphere(r, 3);  // 1280 triangles
  testing::write_obj(sphere, dir.file("sphere.obj"));
  json shape = {{"type", "mesh"},
                {"file", dir.file("sphere.obj")},
                {"transform", {{"translate", {0.5, 0.5, 0.5}}}}};
  Scene s = build_scene(scene_with_shape(shape));
  double volume = 0;
  for (double v : s.particles.vol0) volume += v;
  const double polyhedron = testing::enclosed_volume(sphere);
  const double ball = 4.0 / 3.0 * M_PI * r * r * r;
  EXPECT_NEAR(volume / polyhedron, 1.0, 0.02);
  EXPECT_NEAR(volume / ball, 1.0, 0.03);
}

TEST(MeshShape, MissingTriangleBarelyChangesTheCount) {
  TempDir dir("mesh_hole");
  TriangleMesh cube = testing::unit_cube();
  cube.triangles.erase(cube.triangles.begin() + 11);  // half of the x = 1 face is open
  testing::write_obj(cube, dir.file("holed.obj"));
  const size_t n = particle_count(cube_shape(dir.file("holed.obj")));
  EXPECT_NEAR(double(n), double(kBoxCount), 0.01 * kBoxCount);
}

TEST(MeshShape, HoleInAFineMeshBarelyChangesTheCount) {
  // A hole of several triangles in a sphere: the winding number stays above ½ inside.
  TempDir dir("mesh_sphere_hole");
  TriangleMesh sphere = testing::icosphere(0.2, 3);
  testing::write_obj(sphere, dir.file("closed.obj"));
  sphere.triangles.erase(sphere.triangles.begin() + 100, sphere.triangles.begin() + 108);
  testing::write_obj(sphere, dir.file("holed.obj"));
  auto shape = [&](const std::string& f) {
    return json{
        {"type", "mesh"}, {"file", dir.file(f)}, {"transform", {{"translate", {0.5, 0.5, 0.5}}}}};
  };
  const double closed = double(particle_count(shape("closed.obj")));
  EXPECT_NEAR(double(particle_count(shape("holed.obj"))), closed, 0.01 * closed);
}

TEST(MeshShape, FlippedTrianglesAreRepaired) {
  TempDir dir("mesh_flip");
  TriangleMesh some = testing::unit_cube();
  for (size_t t = 0; t < some.triangles.size(); t += 3)
    std::swap(some.triangles[t][1], some.triangles[t][2]);
  testing::write_obj(some, dir.file("some_flipped.obj"));
  TriangleMesh all = testing::unit_cube();
  for (auto& f : all.triangles) std::swap(f[1], f[2]);  // inside out
  testing::write_obj(all, dir.file("inside_out.obj"));
  EXPECT_EQ(particle_count(cube_shape(dir.file("some_flipped.obj"))), kBoxCount);
  EXPECT_EQ(particle_count(cube_shape(dir.file("inside_out.obj"))), kBoxCount);

  // Flipped and holed at once.
  some.triangles.erase(some.triangles.begin() + 4);
  testing::write_obj(some, dir.file("flipped_holed.obj"));
  EXPECT_NEAR(double(particle_count(cube_shape(dir.file("flipped_holed.obj")))), double(kBoxCount),
              0.01 * kBoxCount);
}

TEST(MeshShape, OrientationRepairCountsFlips) {
  TriangleMesh cube = testing::unit_cube();
  std::swap(cube.triangles[5][1], cube.triangles[5][2]);
  EXPECT_EQ(orient_outward(cube), 1u);
  EXPECT_NEAR(testing::enclosed_volume(cube), 1.0, 1e-12);
}

TEST(MeshShape, FastWindingNumberAgreesWithTheExactSum) {
  TriangleMesh sphere = testing::icosphere(1.0, 4);
  WindingBvh bvh(sphere);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int i = 0; i < 300; ++i) {
    Vec3 q(u(rng), u(rng), u(rng));
    const double exact = bvh.winding_number_exact(q);
    EXPECT_NEAR(bvh.winding_number(q), exact, 0.02) << "at " << q.transpose();
    EXPECT_EQ(exact >= 0.5, q.norm() < 1.0) << "at " << q.transpose();
    // The distance to a fine sphere mesh is nearly | |q| − 1 |.
    EXPECT_NEAR(bvh.distance(q), std::abs(q.norm() - 1.0), 0.01);
  }
}

TEST(MeshShape, CombinesWithCsg) {
  TempDir dir("mesh_csg");
  testing::write_obj(testing::unit_cube(), dir.file("cube.obj"));
  // The cube mesh minus its lower half (a box) leaves half the particles.
  json shape = {{"type", "difference"},
                {"children",
                 {cube_shape(dir.file("cube.obj")),
                  {{"type", "box"}, {"min", {0.2, 0.2, 0.2}}, {"max", {0.6, 0.375, 0.6}}}}}};
  EXPECT_EQ(particle_count(shape), kBoxCount / 2);
}

TEST(MeshShape, RelativePathsResolveAgainstTheSceneFile) {
  TempDir dir("mesh_relative");
  std::filesystem::create_directories(dir.path() / "meshes");
  testing::write_obj(testing::unit_cube(), dir.file("meshes/cube.obj"));
  std::ofstream(dir.file("scene.json")) << scene_with_shape(cube_shape("meshes/cube.obj")).dump(2);
  // The working directory is elsewhere (the build directory), so only the scene's directory
  // can make "meshes/cube.obj" resolve.
  EXPECT_EQ(load_scene(dir.file("scene.json")).particles.size(), kBoxCount);
}

TEST(MeshShape, TenThousandTrianglesFillAHundredThousandPointsInSeconds) {
  TriangleMesh sphere = testing::icosphere(0.25, 5);  // 20,480 triangles
  ShapePtr shape = make_mesh_shape(sphere);
  // 47³ ≈ 104k candidate points around the sphere.
  const Lattice lattice{Vec3(0.25, 0.25, 0.25) - Vec3::Constant(0.27), Vec3::Constant(0.52), 0.0230,
                        2};
  std::vector<Vec3> pts = sample_shape(
      *make_transformed(std::move(shape), Vec3::Constant(0.25), Mat3::Identity(), Vec3::Ones()),
      lattice);
  const double h = lattice.spacing();
  const double volume = double(pts.size()) * h * h * h;
  EXPECT_NEAR(volume / (4.0 / 3.0 * M_PI * std::pow(0.25, 3)), 1.0, 0.03);
}

using testing::error_of;
using testing::expect_contains;

TEST(MeshShape, ErrorsNameTheFileAndTheKey) {
  TempDir dir("mesh_errors");
  const std::string key = "objects[0].shape.file";

  std::string missing = dir.file("nope.obj");
  std::string msg = error_of([&] { particle_count(cube_shape(missing)); });
  expect_contains(msg, key);
  expect_contains(msg, missing);
  expect_contains(msg, "not found");

  std::string garbage = dir.file("garbage.stl");
  std::ofstream(garbage) << "this is not a mesh";
  msg = error_of([&] { particle_count(cube_shape(garbage)); });
  expect_contains(msg, key);
  expect_contains(msg, garbage);
  expect_contains(msg, "cannot read the mesh file");

  std::string empty = dir.file("empty.obj");
  std::ofstream(empty) << "# vertices but no faces\nv 0 0 0\nv 1 0 0\nv 0 1 0\n";
  msg = error_of([&] { particle_count(cube_shape(empty)); });
  expect_contains(msg, key);
  expect_contains(msg, empty);

  // Inside CSG the key path names the child.
  json nested = {{"type", "union"}, {"children", {cube_shape(missing)}}};
  msg = error_of([&] { particle_count(nested); });
  expect_contains(msg, "objects[0].shape.children[0].file");

  msg = error_of([&] { particle_count(json{{"type", "mesh"}, {"file", missing}, {"scal", 2}}); });
  expect_contains(msg, "scal");
}

}  // namespace
}  // namespace nsf
