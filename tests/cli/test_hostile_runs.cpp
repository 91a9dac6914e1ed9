// Run files no simulation writes: positions that are NaN, infinite or absurdly far, and frames
// whose stored bytes are damaged. `nsf render` and `nsf export` must stop with a message naming
// the file and the frame; before, they looped forever fitting the camera, wrote NaN files, or
// aborted (SIGABRT) when a read failed inside the parallel render loop.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "core/error.h"
#include "error_matchers.h"
#include "io/png_render.h"
#include "synthetic_run.h"

namespace {

namespace fs = std::filesystem;
using nsf::testing::expect_contains;
using nsf::testing::run_cli;

// A synthetic run whose particle 7 is at `bad` in frame 1 (of 3).
void write_run_with_bad_position(const std::string& path, const nsf::Vec3& bad) {
  nsf::Particles ps = nsf::testing::synthetic_particles();
  nsf::SimSettings s;
  s.dx = 0.03125;
  s.dt = 1e-3;
  s.substeps = 50;
  nsf::RunWriter w(path, ps, s, "two_blocks", nsf::testing::kSyntheticScene);
  for (int f = 0; f < 3; ++f) {
    nsf::testing::set_synthetic_frame(ps, f);
    if (f == 1) ps.x[7] = bad;
    w.write_frame(ps, 0.05 * f);
  }
  w.finish();
}

// File offset and size of the stored chunk of `dataset` that holds frame `frame`.
void chunk_location(const std::string& path, const char* dataset, hsize_t frame, haddr_t& addr,
                    hsize_t& size) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  const hid_t set = H5Dopen2(file, dataset, H5P_DEFAULT);
  ASSERT_GE(set, 0);
  const hsize_t offset[3] = {frame, 0, 0};
  unsigned mask = 0;
  EXPECT_GE(H5Dget_chunk_info_by_coord(set, offset, &mask, &addr, &size), 0);
  H5Dclose(set);
  H5Fclose(file);
}

// Overwrites bytes in the middle of the chunk of `dataset` holding `frame`, as a bad disk would.
void damage_chunk(const std::string& path, const char* dataset, hsize_t frame) {
  haddr_t addr = 0;
  hsize_t size = 0;
  chunk_location(path, dataset, frame, addr, size);
  ASSERT_GT(size, 64u);
  std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
  f.seekp(static_cast<std::streamoff>(addr + size / 2));
  const std::string junk(32, '\x5a');
  f.write(junk.data(), static_cast<std::streamsize>(junk.size()));
  ASSERT_TRUE(f.good());
}

class HostileRun : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = nsf::testing::fresh_dir("hostile_run"); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

TEST_F(HostileRun, NonFiniteOrFarPositionsAreANamedErrorInRenderAndExport) {
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Case {
    nsf::Vec3 x;
    const char* says;
  };
  const std::vector<Case> cases = {
      {nsf::Vec3(nan, 0.2, 0.5), "not a finite number"},
      {nsf::Vec3(0.3, inf, 0.5), "not a finite number"},
      {nsf::Vec3(0.3, 0.2, -inf), "not a finite number"},
      {nsf::Vec3(1e300, 0.2, 0.5), "1e6 m"},
      {nsf::Vec3(0.3, -1e300, 1e300), "1e6 m"},
      {nsf::Vec3(0.3, 0.2, 2e6), "1e6 m"},
  };
  for (size_t c = 0; c < cases.size(); ++c) {
    const std::string run = path("bad" + std::to_string(c) + ".h5");
    write_run_with_bad_position(run, cases[c].x);
    // `timeout`: the camera fit used to loop forever on 1e300; fail in a minute instead.
    for (const std::string& args :
         {"render '" + run + "' -q --no-video --size 64x48 --out '" + path("frames") + "'",
          "render '" + run + "' -q --no-video --size 64x48 --color speed --view front --out '" +
              path("frames") + "'",
          "export '" + run + "' -q --format vtu --out '" + path("vtu") + "'",
          "export '" + run + "' -q --format ply --out '" + path("ply") + "'"}) {
      std::string out;
      EXPECT_EQ(run_cli(args, out, "timeout 60"), 1) << args << "\n" << out;
      expect_contains(out, "nsf: error: ");
      expect_contains(out, run + ": frame 1, particle 7 has position");
      expect_contains(out, cases[c].says);
    }
  }
}

TEST_F(HostileRun, AStoredSceneNestedTooDeepIsANamedError) {
  // Parsing it is fine; copying its colliders recursed once per level and overflowed the stack.
  const std::string run = path("deep_scene.h5");
  const int levels = 200000;
  nsf::testing::write_synthetic_run(run, 2,
                                    R"({"name": "deep", "colliders": )" + std::string(levels, '[') +
                                        std::string(levels, ']') + "}");
  std::string out;
  EXPECT_EQ(run_cli("render '" + run + "' -q --no-video --out '" + path("frames") + "'", out), 1)
      << out;
  expect_contains(out, "the run's stored scene nests objects and arrays more than 512 levels");
}

TEST_F(HostileRun, FrameBoxRefusesABoxBeyondDoubles) {
  nsf::RenderOptions opt;
  opt.camera.fov_deg = 30;
  const std::string msg = nsf::testing::error_of(
      [&] { nsf::frame_box(opt, nsf::Vec3::Constant(-1e300), nsf::Vec3::Constant(1e300)); });
  expect_contains(msg, "frame_box");
  expect_contains(msg, "not finite");
}

TEST_F(HostileRun, DamagedFrameDataIsANamedErrorNotAnAbort) {
  const std::string run = path("damaged.h5");
  nsf::testing::write_synthetic_run(run, 4);
  // Frame 2 of the stress only: the render plan (positions, object colours) reads fine, so the
  // damage is met in the parallel loop that draws the frames.
  damage_chunk(run, "/frames/tau", 2);
  for (const char* threads : {"1", "2", "4"}) {
    std::string out;
    const std::string args = "render '" + run + "' -q --no-video --size 64x48 --threads " +
                             std::string(threads) + " --out '" + path("frames") + "'";
    EXPECT_EQ(run_cli(args, out), 1) << args << "\n" << out;
    expect_contains(out, "nsf: error: " + run + ": reading frame 2 of /frames/tau");
  }
  std::string out;
  EXPECT_EQ(run_cli("export '" + run + "' -q --out '" + path("vtu") + "'", out), 1) << out;
  expect_contains(out, "reading frame 2 of /frames/tau");
  // Damaged positions are met while planning, before any thread starts.
  damage_chunk(run, "/frames/x", 1);
  EXPECT_EQ(run_cli("render '" + run + "' -q --no-video --out '" + path("frames") + "'", out), 1)
      << out;
  expect_contains(out, "reading frame 1 of /frames/x");
}

}  // namespace
