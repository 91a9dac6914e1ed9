// FrameStore's shares (`mpirun -np K nsf train`, nn/train/gradient_team.h): K processes each hold
// the frames i with i mod K == their share, every frame exactly once, and read any other frame from
// its run file, the same values as a store that holds them all.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "error_matchers.h"
#include "nn/dataset.h"
#include "nn_fixtures.h"

namespace fs = std::filesystem;

namespace {

fs::path shares_dataset() {
  const fs::path dir =
      fs::temp_directory_path() / ("nsf_nn_frame_shares_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  nsf::test::write_synthetic_dataset(dir, 20, 7, 3, {0.5, 1.0, 1.5});
  return dir;
}

void expect_same_frame(const nsf::FrameData& a, const nsf::FrameData& b, size_t i) {
  EXPECT_EQ(a.x, b.x) << "frame " << i;
  EXPECT_EQ(a.tau, b.tau) << "frame " << i;
  EXPECT_EQ(a.C, b.C) << "frame " << i;
}

TEST(NnFrameShares, EveryFrameOnceAndTheSameValuesEverywhere) {
  const fs::path dir = shares_dataset();
  const nsf::Dataset d(dir.string());
  const nsf::FrameStore all(d, 1.0);
  ASSERT_EQ(all.size(), 9u);                // 3 runs of 3 frames
  for (const double budget : {1.0, 0.0}) {  // cached, then streamed from the files
    const nsf::FrameStore s0(d, budget, 0, 2), s1(d, budget, 1, 2);
    EXPECT_EQ(s0.cached(), budget > 0);
    ASSERT_EQ(s0.size(), all.size());  // indices stay global
    for (size_t i = 0; i < all.size(); ++i) {
      EXPECT_NE(s0.holds(i), s1.holds(i)) << "frame " << i << " held by one share exactly";
      EXPECT_EQ(s0.holds(i), i % 2 == 0);
      EXPECT_EQ(s0.sim_of(i), all.sim_of(i));
      expect_same_frame(s0.get(i), all.get(i), i);  // held or read from the file
      expect_same_frame(s1.get(i), all.get(i), i);
    }
  }
  fs::remove_all(dir);
}

// A basis model's store holds x alone (a sixth of the memory); τ and C read one field at a time
// from the run files are the floats the full frame holds.
TEST(NnFrameShares, APositionsOnlyStoreHoldsTheSameXAndTheFieldsReadAloneMatch) {
  const fs::path dir = shares_dataset();
  const nsf::Dataset d(dir.string());
  const nsf::FrameStore all(d, 1.0);
  for (const double budget : {1.0, 0.0}) {
    const nsf::FrameStore x_only(d, budget, 0, 1, true);
    EXPECT_TRUE(x_only.positions_only());
    EXPECT_EQ(x_only.cached(), budget > 0);
    EXPECT_NEAR(x_only.cached_gib() * 6, budget > 0 ? 9 * 20 * 18 * 4 / 1073741824.0 : 0, 1e-12);
    for (size_t i = 0; i < all.size(); ++i) {
      const nsf::FrameData& f = x_only.get(i);
      EXPECT_EQ(f.x, all.get(i).x) << "frame " << i;
      EXPECT_TRUE(f.tau.empty() && f.C.empty());
      const nsf::SimulationFile& run = d.train()[all.sim_of(i)];
      const nsf::FrameData& full = all.get(i);
      EXPECT_EQ(d.read_field(run, all.frame_of(i), "tau"), full.tau) << "frame " << i;
      EXPECT_EQ(d.read_field(run, all.frame_of(i), "C"), full.C) << "frame " << i;
      EXPECT_EQ(d.read_field(run, all.frame_of(i), "x"), full.x) << "frame " << i;
    }
  }
  fs::remove_all(dir);
}

TEST(NnFrameShares, AShareThatDoesNotExistIsRefused) {
  const fs::path dir = shares_dataset();
  const nsf::Dataset d(dir.string());
  using nsf::testing::expect_error;
  expect_error([&] { nsf::FrameStore(d, 1.0, 2, 2); }, {"share 2 of 2 does not exist"});
  expect_error([&] { nsf::FrameStore(d, 1.0, 0, 0); }, {"share 0 of 0 does not exist"});
  fs::remove_all(dir);
}

}  // namespace
