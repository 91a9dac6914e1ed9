// Sweeps: the "sweep" scene section, the μ plan, template expansion, and `run_sweep` writing,
// resuming and listing its runs.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include "core/error.h"
#include "data/sweep.h"
#include "data/sweep_spec.h"
#include "io/run_reader.h"
#include "mpm/scene/scene.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// A box of 4x4x4 cells (512 particles), 2 frames of 2 steps: a run takes milliseconds.
json tiny_scene() {
  return json::parse(R"({
    "name": "tiny",
    "simulation": { "dx": 0.125, "dt": 1e-3, "frames": 2, "substeps": 2, "ppc": 2 },
    "objects": [ { "shape": { "type": "box", "min": [0.375, 0.375, 0.375], "max": [0.625, 0.625, 0.625] },
                   "material": { "type": "fixed_corotated", "E": 1000, "nu": 0.3 } } ],
    "sweep": { "parameter": "youngs_modulus", "set": ["material.E={mu*1000}"],
               "range": [1, 3], "train": 3, "test": 2 }
  })");
}

nsf::SweepSpec spec(double lo, double hi, int train, int test) {
  nsf::SweepSpec s;
  s.parameter = "p";
  s.set = {"material.E={mu}"};
  s.lo = lo, s.hi = hi, s.train = train, s.test = test;
  return s;
}

TEST(SweepPlan, TrainingSpansTheRangeAndTestsSitAtMidpoints) {
  const std::vector<nsf::SweepRun> runs = nsf::plan_sweep(spec(20, 40, 5, 2));
  ASSERT_EQ(runs.size(), 7u);
  const double train[] = {20, 25, 30, 35, 40};
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(runs[i].split, "train");
    EXPECT_EQ(runs[i].index, i);
    EXPECT_DOUBLE_EQ(runs[i].mu, train[i]);
  }
  // Intervals floor((k + 1/2) * 4 / 2) = 1 and 3.
  EXPECT_EQ(runs[5].file(), "test_0.h5");
  EXPECT_DOUBLE_EQ(runs[5].mu, 27.5);
  EXPECT_DOUBLE_EQ(runs[6].mu, 37.5);
}

TEST(SweepPlan, AsManyTestsAsIntervalsUsesEveryInterval) {
  const std::vector<nsf::SweepRun> runs = nsf::plan_sweep(spec(0, 3, 4, 3));
  EXPECT_DOUBLE_EQ(runs[4].mu, 0.5);
  EXPECT_DOUBLE_EQ(runs[5].mu, 1.5);
  EXPECT_DOUBLE_EQ(runs[6].mu, 2.5);
}

TEST(SweepTemplates, ExpandExpressions) {
  nsf::SweepSpec s = spec(0, 1, 2, 0);
  s.set = {"a={mu}", "b=[{mu*-2},{cos_deg(mu)},{sin_deg(mu)*10}]", "c={tan_deg(mu)}"};
  const std::vector<std::string> o = nsf::sweep_overrides(s, 30);
  EXPECT_EQ(o[0], "a=30.0");
  const json b = json::parse(o[1].substr(2));
  EXPECT_DOUBLE_EQ(b[0].get<double>(), -60);
  EXPECT_NEAR(b[1].get<double>(), std::sqrt(3.0) / 2, 1e-15);
  EXPECT_NEAR(b[2].get<double>(), 5, 1e-14);
  EXPECT_NEAR(json::parse(o[2].substr(2)).get<double>(), 1 / std::sqrt(3.0), 1e-15);
  // Offsets place a part relative to a pivot; numbers may carry signs and exponents.
  s.set = {"a=[{mu+1},{mu*2-1},{cos_deg(mu)*-0.5+2},{sin_deg(mu)-1e-1},{mu*1e-2+3}]"};
  const json a = json::parse(nsf::sweep_overrides(s, 60)[0].substr(2));
  EXPECT_DOUBLE_EQ(a[0].get<double>(), 61);
  EXPECT_DOUBLE_EQ(a[1].get<double>(), 119);
  EXPECT_NEAR(a[2].get<double>(), 1.75, 1e-15);
  EXPECT_NEAR(a[3].get<double>(), std::sqrt(3.0) / 2 - 0.1, 1e-15);
  EXPECT_NEAR(a[4].get<double>(), 3.6, 1e-15);
  for (const char* bad : {"a={mu*x}", "a={mu+}", "a={mu+1x}", "a={mu++1}", "a={mu+-1}", "a={1+mu}",
                          "a={mu*2*3}", "a={mu-1*2}"}) {
    s.set = {bad};
    EXPECT_THROW(nsf::sweep_overrides(s, 1), nsf::Error) << bad;
  }
}

// Each broken section fails with a message naming the key. The engine's loader leaves the section
// to its owner (the commands check it whenever they load a scene: rom/setup/scene_file.h).
TEST(SweepSection, NamesTheKeyAtFault) {
  EXPECT_NO_THROW(nsf::parse_sweep(tiny_scene().at("sweep"), tiny_scene()));
  auto fails_with = [](const char* key, const json& value, const char* needle) {
    json j = tiny_scene();
    j["sweep"][key] = value;
    EXPECT_NO_THROW(nsf::build_scene(j));
    try {
      nsf::parse_sweep(j.at("sweep"), j);
      ADD_FAILURE() << key << " = " << value.dump() << " was accepted";
    } catch (const nsf::Error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  fails_with("seeds", 1, "seeds");
  fails_with("design", "grid3", "sweep.design");
  fails_with("vary", json::array(), "sweep.vary");
  fails_with("range", json::array({3, 1}), "sweep.range");
  fails_with("train", 1, "sweep.train");
  fails_with("test", 3, "sweep.test");  // only 2 intervals between 3 training values
  fails_with("set", json::array({"material.E=5"}), "sweep.set[0]");
  fails_with("set", json::array({"materal.E={mu}"}), "materal");
  fails_with("set", json::array({"material.E={2*mu}"}), "2*mu");
}

class SweepRunTest : public testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::path(testing::TempDir()) /
        ("nsf_sweep_" + std::string(testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    scene_ = (dir_ / "tiny.json").string();
    std::ofstream(scene_) << tiny_scene().dump(2);
  }
  void TearDown() override { fs::remove_all(dir_); }

  nsf::SweepSummary sweep(const std::string& out, int jobs = 1,
                          std::vector<std::string> overrides = {}, const std::string& only = "",
                          int gzip = 0) {
    nsf::SweepOptions o;
    o.out_dir = (dir_ / out).string();
    o.jobs = jobs;
    o.gzip = gzip;
    o.quiet = true;
    o.overrides = std::move(overrides);
    o.only = only;
    return nsf::run_sweep(scene_, o);
  }
  json manifest(const std::string& out) {
    return json::parse(std::ifstream(dir_ / out / "manifest.json"));
  }

  fs::path dir_;
  std::string scene_;
};

TEST_F(SweepRunTest, WritesEveryRunWithItsMuAndAManifest) {
  const nsf::SweepSummary s = sweep("data", 2);
  EXPECT_EQ(s.planned, 5);
  EXPECT_EQ(s.ran, 5);
  EXPECT_EQ(s.skipped, 0);
  const json m = manifest("data");
  EXPECT_EQ(m["sweep_parameter"], "youngs_modulus");
  ASSERT_EQ(m["runs"].size(), 5u);
  const std::map<std::string, std::pair<std::string, double>> want = {{"train_0.h5", {"train", 1}},
                                                                      {"train_1.h5", {"train", 2}},
                                                                      {"train_2.h5", {"train", 3}},
                                                                      {"test_0.h5", {"test", 1.5}},
                                                                      {"test_1.h5", {"test", 2.5}}};
  for (const json& run : m["runs"]) {
    const std::string file = run["file"];
    ASSERT_TRUE(want.count(file)) << file;
    EXPECT_EQ(run["split"], want.at(file).first);
    EXPECT_DOUBLE_EQ(run["mu"].get<double>(), want.at(file).second);
    nsf::RunReader r((dir_ / "data" / file).string());
    EXPECT_EQ(r.frame_count(), 3u);
    EXPECT_DOUBLE_EQ(r.attribute_double("mu"), want.at(file).second);
    EXPECT_EQ(r.attribute_string("split"), want.at(file).first);
    EXPECT_EQ(r.attribute_string("sweep_parameter"), "youngs_modulus");
    const json scene = json::parse(r.scene_json());
    EXPECT_DOUBLE_EQ(scene["objects"][0]["material"]["E"].get<double>(),
                     1000 * want.at(file).second);
  }
  EXPECT_FALSE(fs::exists(dir_ / "data" / "manifest.json.tmp"));
}

TEST_F(SweepRunTest, ResumesWithoutRedoingFinishedRuns) {
  sweep("data");
  const fs::path d = dir_ / "data";
  std::map<std::string, fs::file_time_type> before;
  for (const char* f : {"train_0.h5", "train_2.h5", "test_0.h5", "test_1.h5"})
    before[f] = fs::last_write_time(d / f);
  // An interrupted run: its final file is gone and a half-written .tmp is left behind.
  fs::remove(d / "train_1.h5");
  std::ofstream(d / "train_1.h5.tmp") << "half a file";
  // A damaged one: a truncated final file is not complete either.
  fs::resize_file(d / "test_1.h5", 100);

  const nsf::SweepSummary s = sweep("data");
  EXPECT_EQ(s.ran, 2);
  EXPECT_EQ(s.skipped, 3);
  for (const char* f : {"train_0.h5", "train_2.h5", "test_0.h5"})
    EXPECT_EQ(fs::last_write_time(d / f), before[f]) << f << " was redone";
  EXPECT_NO_THROW(nsf::RunReader((d / "train_1.h5").string()));
  EXPECT_NO_THROW(nsf::RunReader((d / "test_1.h5").string()));
  EXPECT_FALSE(fs::exists(d / "train_1.h5.tmp"));
  EXPECT_EQ(manifest("data")["runs"].size(), 5u);

  // Nothing left to do.
  EXPECT_EQ(sweep("data").ran, 0);
}

TEST_F(SweepRunTest, ChangedSceneRedoesEverything) {
  sweep("data");
  EXPECT_EQ(sweep("data", 1, {"material.nu=0.25"}).ran, 5);
}

TEST_F(SweepRunTest, EditsThatDoNotChangeTheSimulationRedoNothing) {
  sweep("data");
  json scene = tiny_scene();
  scene["description"] = "another text";
  scene["rom"] = {{"samples", 7}};
  std::ofstream(scene_) << scene.dump(2);
  EXPECT_EQ(sweep("data").ran, 0);
}

TEST_F(SweepRunTest, SplitsCanBeRunSeparately) {
  EXPECT_EQ(sweep("data", 1, {}, "test").ran, 2);
  EXPECT_EQ(manifest("data")["runs"].size(), 2u);
  const nsf::SweepSummary s = sweep("data", 1, {}, "train");
  EXPECT_EQ(s.planned, 3);
  EXPECT_EQ(s.ran, 3);
  EXPECT_EQ(manifest("data")["runs"].size(), 5u);
}

TEST_F(SweepRunTest, ParallelJobsGiveTheSameBits) {
  sweep("one", 1);
  sweep("two", 2);
  for (const char* f : {"train_0.h5", "test_1.h5"}) {
    nsf::RunReader a((dir_ / "one" / f).string()), b((dir_ / "two" / f).string());
    EXPECT_EQ(a.read_positions(2), b.read_positions(2)) << f;
  }
}

// `nsf sweep --gzip`: the same runs, every frame bit for bit, in smaller files; a compressed
// sweep resumes like any other.
TEST_F(SweepRunTest, CompressedRunsHoldTheSameBitsInLessSpace) {
  sweep("plain");
  sweep("gzip", 1, {}, "", 6);
  for (const char* f : {"train_0.h5", "test_1.h5"}) {
    const fs::path a = dir_ / "plain" / f, b = dir_ / "gzip" / f;
    nsf::RunReader ra(a.string()), rb(b.string());
    for (size_t i = 0; i < ra.frame_count(); ++i) {
      const nsf::RunFrame fa = ra.read_frame(i), fb = rb.read_frame(i);
      EXPECT_EQ(fa.x, fb.x) << f;
      EXPECT_EQ(fa.F, fb.F) << f;
      EXPECT_EQ(fa.tau, fb.tau) << f;
    }
    EXPECT_LT(fs::file_size(b), fs::file_size(a)) << f;
  }
  EXPECT_EQ(sweep("gzip", 1, {}, "", 6).skipped, 5);
}

// Two processes of one sweep (what app/sweep_ranks.cpp does over MPI), run one after the other
// in this one: the first call's pending list decides for both, as process 0's does over MPI;
// process 1 reports its finished runs, process 0 writes the manifest with them.
struct TwoProcessTeam {
  std::vector<int> pending;
  bool decided = false;
  std::vector<int> reported;  // by process 1
  int manifests = 0;
  std::vector<int> ran[2];

  struct Member : nsf::SweepTeam {
    Member(TwoProcessTeam& t, int r) : team(t), rank(r) {}
    std::vector<int> share(const std::vector<int>& p) override {
      if (!team.decided) team.pending = p, team.decided = true;
      std::vector<int> mine;
      for (size_t k = size_t(rank); k < team.pending.size(); k += 2)
        mine.push_back(team.pending[k]);
      return mine;
    }
    void collect(const std::vector<int>& done,
                 const std::function<void(const std::vector<int>&)>& write_manifest) override {
      team.ran[rank] = done;
      if (rank == 1) {
        team.reported = done;
        return;
      }
      std::vector<int> all = done;
      all.insert(all.end(), team.reported.begin(), team.reported.end());
      write_manifest(all);
      ++team.manifests;
    }
    TwoProcessTeam& team;
    int rank;
  };
};

std::string bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST_F(SweepRunTest, TeamSharesThePendingRunsAndWritesOneManifestOfAll) {
  sweep("one");
  TwoProcessTeam team;
  TwoProcessTeam::Member p0(team, 0), p1(team, 1);
  nsf::SweepOptions o;
  o.out_dir = (dir_ / "two").string();
  o.quiet = true;
  o.team = &p1;
  nsf::run_sweep(scene_, o);
  EXPECT_FALSE(fs::exists(dir_ / "two" / "manifest.json")) << "process 1 wrote the manifest";
  // A network file system may not show process 0 another host's new file yet: the manifest
  // still lists it, because process 1 reported it.
  fs::rename(dir_ / "two" / "train_1.h5", dir_ / "hidden.h5");
  o.team = &p0;
  const nsf::SweepSummary s = nsf::run_sweep(scene_, o);
  fs::rename(dir_ / "hidden.h5", dir_ / "two" / "train_1.h5");

  // Runs 0..4 pending: process 0 takes 0, 2, 4 and process 1 takes 1, 3.
  EXPECT_EQ(team.ran[0], (std::vector<int>{0, 2, 4}));
  EXPECT_EQ(team.ran[1], (std::vector<int>{1, 3}));
  EXPECT_EQ(team.manifests, 1);
  EXPECT_EQ(s.ran, 5);
  EXPECT_EQ(manifest("two"), manifest("one"));
  for (const char* f : {"train_0.h5", "train_1.h5", "train_2.h5", "test_0.h5", "test_1.h5"})
    EXPECT_EQ(bytes(dir_ / "two" / f), bytes(dir_ / "one" / f)) << f;
}

TEST_F(SweepRunTest, TeamResumesOnlyWhatIsMissing) {
  sweep("data");
  fs::remove(dir_ / "data" / "train_2.h5");
  fs::remove(dir_ / "data" / "test_0.h5");
  TwoProcessTeam team;
  TwoProcessTeam::Member p0(team, 0), p1(team, 1);
  nsf::SweepOptions o;
  o.out_dir = (dir_ / "data").string();
  o.quiet = true;
  o.team = &p1;
  EXPECT_EQ(nsf::run_sweep(scene_, o).skipped, 3);
  o.team = &p0;
  const nsf::SweepSummary s = nsf::run_sweep(scene_, o);
  EXPECT_EQ(team.ran[0], (std::vector<int>{2}));
  EXPECT_EQ(team.ran[1], (std::vector<int>{3}));
  EXPECT_EQ(s.ran, 2);
  EXPECT_EQ(manifest("data")["runs"].size(), 5u);
}

TEST_F(SweepRunTest, BrokenSweepIsAnErrorNamingFileAndKey) {
  json j = tiny_scene();
  j["sweep"]["range"] = {3, 1};
  std::ofstream(scene_) << j.dump();
  try {
    sweep("data");
    ADD_FAILURE() << "a broken sweep was run";
  } catch (const nsf::Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(scene_), std::string::npos) << what;
    EXPECT_NE(what.find("sweep.range"), std::string::npos) << what;
  }
}

TEST_F(SweepRunTest, SceneWithoutSweepIsAnError) {
  json j = tiny_scene();
  j.erase("sweep");
  std::ofstream(scene_) << j.dump();
  EXPECT_THROW(sweep("data"), nsf::Error);
}

}  // namespace
