// The training family a model records (data/scene_family.h): every value of its training runs'
// scenes, and what of a new scene lies outside.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/error.h"
#include "data/scene_family.h"
#include "data/training_box.h"

namespace {

using nlohmann::json;
using ::testing::HasSubstr;

// A scene of the kind `nsf sweep` stores: the sweep's templates applied (here, the plate's stop
// time and the hardening).
json run_scene(double stop, double hardening) {
  json s = json::parse(R"({
    "name": "plates", "description": "two plates", "camera": {"eye": [1, 1, 1]},
    "simulation": {"dx": 0.02, "dt": 0.001, "frames": 32, "cfl": 0.6},
    "objects": [{"shape": "box", "material": {"model": "von_mises", "hardening": 0}}],
    "colliders": [{"type": "plane", "point": [0, 0.1, 0], "normal": [0, 1, 0]},
                  {"type": "box", "motion": {"keyframes": [{"t": 0, "center": [0.3, 0.3, 0.5]},
                                                           {"t": 0.2, "center": [0.36, 0.3, 0.5]}]}}],
    "sweep": {"parameter": "hardening", "range": [0, 0.2]},
    "rom": {"samples": 200}, "train": {"epochs": 3}, "generalize": {"draws": 10}
  })");
  s["colliders"][1]["motion"]["keyframes"][1]["t"] = stop;
  s["objects"][0]["material"]["hardening"] = hardening;
  return s;
}

nsf::SceneFamily family() {
  nsf::SceneFamily f = nsf::SceneFamily::of(run_scene(0.2, 0.0));
  f.include(nsf::SceneFamily::of(run_scene(0.2, 0.1)));
  f.include(nsf::SceneFamily::of(run_scene(0.2, 0.2)));
  return f;
}

TEST(SceneFamily, HoldsEveryValueOfTheTrainingRunsAndTheRangeOfThoseThatVaried) {
  const nsf::SceneFamily f = family();
  EXPECT_EQ(f.runs(), 3);
  EXPECT_EQ(f.varying(), 1u);  // the hardening
  // Each run of the family, and a value between the runs, lies inside.
  for (double h : {0.0, 0.05, 0.2}) EXPECT_TRUE(f.outside(run_scene(0.2, h)).empty()) << h;
  // What does not change the simulation is not the family's: names, cameras, the ROM's and
  // the trainer's sections, the sweep and the benchmark, and the CFL factor.
  json edited = run_scene(0.2, 0.1);
  edited["name"] = "other", edited["description"] = "", edited["camera"]["eye"] = {2, 2, 2};
  edited["rom"] = {{"samples", 50}}, edited["train"] = json::object();
  edited["sweep"] = nullptr, edited["generalize"] = json::object();
  edited["simulation"]["cfl"] = 0.85;
  EXPECT_TRUE(f.outside(edited).empty());
}

TEST(SceneFamily, SaysWhatLiesOutside) {
  const nsf::SceneFamily f = family();
  // A faster plate: a value the runs never varied.
  std::vector<std::string> out = f.outside(run_scene(0.17, 0.1));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_THAT(out[0], HasSubstr("/colliders/1/motion/keyframes/1/t = 0.17, outside [0.2, 0.2]"));
  // A swept value beyond its range, within the rounding allowed and beyond it.
  EXPECT_TRUE(f.outside(run_scene(0.2, 0.2 * (1 + 1e-9))).empty());
  out = f.outside(run_scene(0.2, 0.25));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_THAT(out[0], HasSubstr("/objects/0/material/hardening = 0.25, outside [0, 0.2]"));
  // Another value of a text, a key no run had, and one every run had and this scene lacks.
  json s = run_scene(0.2, 0.1);
  s["objects"][0]["material"]["model"] = "drucker_prager";
  s["colliders"][0]["friction"] = 0.3;
  s["simulation"].erase("frames");
  out = f.outside(s);
  ASSERT_EQ(out.size(), 3u);
  // (in the scene's key order)
  EXPECT_THAT(out[0], HasSubstr("/colliders/0/friction = 0.3, which no training run"));
  EXPECT_THAT(out[1], HasSubstr("/objects/0/material/model = \"drucker_prager\", not "
                                "\"von_mises\""));
  EXPECT_THAT(out[2], HasSubstr("/simulation/frames is missing"));
  // A second plate: every one of its values is new.
  s = run_scene(0.2, 0.1);
  s["colliders"].push_back(s["colliders"][1]);
  EXPECT_GT(f.outside(s).size(), 3u);
  // A model that never recorded its family says nothing.
  EXPECT_TRUE(nsf::SceneFamily().outside(s).empty());
}

TEST(SceneFamily, AKeyOnlySomeRunsHadMayBeMissingAndTheFamilyReadsBack) {
  nsf::SceneFamily f = family();
  json extra = run_scene(0.2, 0.1);
  extra["colliders"][0]["friction"] = 0.3;
  f.include(nsf::SceneFamily::of(extra));
  EXPECT_TRUE(f.outside(run_scene(0.2, 0.1)).empty());  // not every run had it
  EXPECT_TRUE(f.outside(extra).empty());
  // Through a training box's JSON, as the model file stores it.
  nsf::TrainingBox box;
  box.scene = f;
  const nsf::TrainingBox back = nsf::TrainingBox::from_json(box.to_json(), "test");
  EXPECT_EQ(back.to_json(), box.to_json());
  EXPECT_EQ(back.scene.outside(run_scene(0.17, 0.1)), f.outside(run_scene(0.17, 0.1)));
  for (const char* bad :
       {R"({"runs": 1})", R"({"runs": -1, "values": {}})", R"({"runs": 1, "values": {"/a": 3}})",
        R"({"runs": 1, "values": {"/a": {"range": [2, 1]}}})",
        R"({"runs": 1, "values": {"/a": {"values": [3]}}})",
        R"({"runs": 1, "values": {"/a": {}}})"})
    EXPECT_THROW(nsf::SceneFamily::from_json(json::parse(bad), "test"), nsf::Error) << bad;
}

}  // namespace
