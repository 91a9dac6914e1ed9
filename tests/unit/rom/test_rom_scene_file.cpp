// The commands' check of a whole scene (rom/setup/scene_file.h): the engine's loader reads its own
// sections, and the "sweep", "rom" and "train" sections are parsed by their owners, so that a
// misspelt key anywhere still stops every command that loads the scene.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "rom/setup/scene_file.h"

namespace nsf::app {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

json small_scene() {
  return json::parse(R"({
    "name": "small",
    "simulation": {"dx": 0.125, "dt": 1e-3, "frames": 2, "substeps": 2},
    "objects": [{
      "shape": {"type": "box", "min": [0.375, 0.375, 0.375], "max": [0.625, 0.625, 0.625]},
      "material": {"type": "fixed_corotated", "E": 1000, "nu": 0.3}
    }],
    "sweep": {"parameter": "youngs_modulus", "set": ["material.E={mu*1000}"], "range": [1, 3],
              "train": 3, "test": 1},
    "rom": {"samples": 20, "dt_ratio": 2},
    "train": {"steps": [10, 20, 30]}
  })");
}

fs::path write_scene(const std::string& name, const json& j) {
  const fs::path p = fs::path(testing::TempDir()) / name;
  std::ofstream(p) << j.dump(2);
  return p;
}

std::string error_of(const fs::path& p) {
  try {
    read_scene_file(p.string());
  } catch (const Error& e) {
    return e.what();
  }
  return "<no error>";
}

TEST(SceneFile, ParsesEachSectionOnceByItsOwner) {
  const SceneFile f =
      read_scene_file(write_scene("sections.json", small_scene()).string(), {"rom.samples=30"});
  ASSERT_TRUE(f.sections.sweep.has_value());
  EXPECT_EQ(f.sections.sweep->parameter, "youngs_modulus");
  EXPECT_EQ(f.sections.rom.sampling.count, 30);  // overrides apply first
  ASSERT_TRUE(f.sections.rom.dt_ratio.has_value());
  EXPECT_DOUBLE_EQ(*f.sections.rom.dt_ratio, 2.0);
  ASSERT_TRUE(f.sections.train.has_value());
  EXPECT_EQ(f.sections.train->steps, (std::array<long, 3>{10, 20, 30}));
  EXPECT_EQ(build_scene_file(f).name, "small");

  json j = small_scene();
  for (const char* key : {"sweep", "rom", "train"}) j.erase(key);
  const SceneFile none = read_scene_file(write_scene("no_sections.json", j).string());
  EXPECT_FALSE(none.sections.sweep.has_value());
  EXPECT_FALSE(none.sections.train.has_value());
  EXPECT_EQ(none.sections.rom.sampling.count, SamplingSpec().count);
}

// The engine's loader alone accepts these (it does not read the sections); the commands do not.
TEST(SceneFile, AMisspeltKeyInAnySectionNamesTheFileAndTheKey) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"sweep", "rnage"}, {"rom", "sampels"}, {"train", "stpes"}};
  for (const auto& [section, key] : cases) {
    json j = small_scene();
    j[section][key] = 1;
    EXPECT_NO_THROW(build_scene(j)) << section;
    const fs::path p = write_scene("misspelt_" + section + ".json", j);
    const std::string msg = error_of(p);
    EXPECT_NE(msg.find(p.filename().string()), std::string::npos) << msg;
    EXPECT_NE(msg.find(section + "." + key), std::string::npos) << msg;
  }
  json j = small_scene();
  j["simulation"]["dtt"] = 1;  // the engine's own sections: build_scene_file
  const fs::path p = write_scene("misspelt_simulation.json", j);
  try {
    build_scene_file(read_scene_file(p.string()));
    ADD_FAILURE() << "accepted simulation.dtt";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("simulation.dtt"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(p.filename().string()), std::string::npos) << e.what();
  }
}

// Every scene in scenes/ passes the commands' check of its sections.
TEST(SceneFile, EveryShippedSceneParses) {
  size_t checked = 0;
  for (const auto& entry : fs::recursive_directory_iterator(fs::path(NSF_SOURCE_DIR) / "scenes")) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    EXPECT_NO_THROW(read_scene_file(entry.path().string()));
    ++checked;
  }
  EXPECT_GE(checked, 20u);
}

}  // namespace
}  // namespace nsf::app
