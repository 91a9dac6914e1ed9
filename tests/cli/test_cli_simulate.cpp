// `nsf simulate` end to end: a good scene gives a complete file; bad input gives a message that
// names the problem, a non-zero exit, and no output file.
#include <gtest/gtest.h>

#include <fstream>

#include "cli_runner.h"
#include "cli_scene_fixture.h"
#include "io/run_reader.h"

namespace nsf {
namespace {

namespace fs = std::filesystem;
using testing::run_cli;

const std::string kTinyScene = nsf::testing::tiny_cli_scene(3);

fs::path write_scene(const fs::path& dir, const std::string& text) {
  fs::path p = dir / "scene.json";
  std::ofstream(p) << text;
  return p;
}

TEST(CliSimulate, WritesCompleteRunAndPicture) {
  fs::path d = testing::fresh_dir("sim_ok");
  fs::path scene = write_scene(d, kTinyScene);
  auto r = run_cli("simulate " + scene.string() + " --out " + (d / "run.h5").string() + " --png " +
                   (d / "run.png").string() + " -j 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("particle-steps/s"), std::string::npos) << r.output;
  RunReader run((d / "run.h5").string());
  EXPECT_EQ(run.frame_count(), 4u);
  EXPECT_GT(run.particle_count(), 0u);
  EXPECT_TRUE(fs::exists(d / "run.png"));
  EXPECT_FALSE(fs::exists(d / "run.h5.tmp"));
  // The box fell under gravity.
  EXPECT_LT(run.read_frame(3).x[0][1], run.read_frame(0).x[0][1]);
}

// --gzip: the same frames bit for bit (one thread each, so the runs are identical) in a smaller
// file; a level past 9 is a usage error naming the option.
TEST(CliSimulate, GzipWritesTheSameFramesInASmallerFile) {
  fs::path d = testing::fresh_dir("sim_gzip");
  fs::path scene = write_scene(d, kTinyScene);
  const std::string base = "simulate " + scene.string() + " -j 1 -q --out ";
  ASSERT_EQ(run_cli(base + (d / "plain.h5").string()).exit_code, 0);
  auto r = run_cli(base + (d / "gzip.h5").string() + " --gzip 1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  RunReader plain((d / "plain.h5").string()), gzip((d / "gzip.h5").string());
  ASSERT_EQ(gzip.frame_count(), plain.frame_count());
  for (size_t i = 0; i < plain.frame_count(); ++i) {
    const RunFrame a = plain.read_frame(i), b = gzip.read_frame(i);
    EXPECT_EQ(a.x, b.x);
    EXPECT_EQ(a.v, b.v);
    EXPECT_EQ(a.C, b.C);
  }
  EXPECT_LT(fs::file_size(d / "gzip.h5"), fs::file_size(d / "plain.h5"));
  r = run_cli(base + (d / "bad.h5").string() + " --gzip 10");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--gzip"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "bad.h5"));
}

TEST(CliSimulate, OverrideIsApplied) {
  fs::path d = testing::fresh_dir("sim_set");
  fs::path scene = write_scene(d, kTinyScene);
  auto r = run_cli("simulate " + scene.string() + " --out " + (d / "run.h5").string() +
                   " --set simulation.frames=1 -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(RunReader((d / "run.h5").string()).frame_count(), 2u);
}

struct BadCase {
  const char* what;
  std::string scene_text;
  std::string extra_args;
  const char* message_part;
};

TEST(CliSimulate, BadInputFailsCleanly) {
  std::string tiny = kTinyScene;
  auto replace = [&](const std::string& from, const std::string& to) {
    std::string s = tiny;
    s.replace(s.find(from), from.size(), to);
    return s;
  };
  const BadCase cases[] = {
      {"out-of-range value", replace("\"nu\": 0.3", "\"nu\": 0.7"), "", "nu"},
      {"unknown key", replace("\"substeps\": 4", "\"substeps\": 4, \"dtt\": 1"), "", "dtt"},
      {"malformed JSON", replace("\"frames\": 3,", "\"frames\": 3,,"), "", "JSON"},
      {"bad override", tiny, "--set simulation.nope.x=1", "nope"},
      {"dt over the CFL bound", replace("\"dt\": 5e-4", "\"dt\": 5e-2"), "", "CFL"},
      {"particle speed over the CFL limit",
       replace("\"nu\": 0.3}", "\"nu\": 0.3}, \"velocity\": [0, 0, 40]"), "", "particle"},
  };
  for (const BadCase& c : cases) {
    fs::path d = testing::fresh_dir("sim_bad");
    fs::path scene = write_scene(d, c.scene_text);
    auto r = run_cli("simulate " + scene.string() + " --out " + (d / "run.h5").string() + " " +
                     c.extra_args + " -q");
    EXPECT_NE(r.exit_code, 0) << c.what;
    EXPECT_NE(r.output.find(c.message_part), std::string::npos) << c.what << ": " << r.output;
    EXPECT_FALSE(fs::exists(d / "run.h5")) << c.what;
    EXPECT_FALSE(fs::exists(d / "run.h5.tmp")) << c.what;
  }
}

TEST(CliSimulate, MissingSceneFile) {
  auto r = run_cli("simulate /nonexistent/scene.json --out /tmp/x.h5");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("scene.json"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace nsf
