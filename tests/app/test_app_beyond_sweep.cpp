// The beyond-sweep cases of `nsf report --beyond-sweep` (app/beyond_sweep.h): each changes its
// scene, at both sizes, and the scene still builds.
#include <gtest/gtest.h>

#include <filesystem>

#include "app/beyond_sweep.h"
#include "rom/setup/scene_file.h"

namespace fs = std::filesystem;

TEST(BeyondSweep, EveryCaseChangesItsSceneAtBothSizesAndTheSceneBuilds) {
  int cases = 0;
  for (const char* base : {"bread", "cake", "sand", "metal", "toothpaste", "jelly", "squishy_ball"})
    for (const nsf::app::BeyondSweepCase& c : nsf::app::beyond_sweep_cases(base)) {
      ++cases;
      EXPECT_EQ(c.set.empty(), !c.at_test_mu) << base << ": a case changes the scene or mu";
      for (const char* size : {"_small", "_paper"}) {
        const std::string path =
            (fs::path(NSF_SOURCE_DIR) / "scenes" / "paper" / (base + std::string(size) + ".json"))
                .string();
        const nsf::SceneFile plain = nsf::read_scene_file(path);
        const nsf::SceneFile changed = nsf::read_scene_file(path, c.set);
        if (!c.set.empty()) {
          EXPECT_NE(plain.json, changed.json) << path << ": " << c.what;
        }
        EXPECT_NO_THROW(nsf::build_scene_file(changed)) << path << ": " << c.what;
      }
    }
  EXPECT_GE(cases, 3);  // issue #25 point 5: at least three scenes
  EXPECT_TRUE(nsf::app::beyond_sweep_cases("no_such_scene").empty());
}
