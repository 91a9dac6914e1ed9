// A bounded mutation fuzz of the scene reader (#28 item 21): the shipped scenes and the scenes in
// docs/SCENES.md, mutated (keys deleted, duplicated or misspelt, types swapped, extreme numbers,
// hostile strings, deep nesting, byte flips, truncation, --set overrides) and read and built as
// the commands do. Every case must be accepted or stop with nsf::Error, within a time limit; a
// crash, a hang or another exception fails the test with the case, its seed and a file holding
// it. Replay: NSF_FUZZ_SEED=<seed> [NSF_FUZZ_ONLY=<case>] nsf_tests --gtest_filter='FuzzScene.*'
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "core/error.h"
#include "data/sweep_spec.h"
#include "fuzz_harness.h"
#include "json_mutator.h"
#include "mpm/scene/scene.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace nsf::testing::fuzz;

struct Seed {
  std::string name;
  std::string dir;  // where its relative mesh paths resolve
  json doc;
};

// The shipped example and small paper scenes, and the whole scenes of docs/SCENES.md.
std::vector<Seed> corpus() {
  std::vector<Seed> out;
  const fs::path root(NSF_SOURCE_DIR);
  for (const char* sub : {"scenes/examples", "scenes/paper"}) {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(root / sub)) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const fs::path& p : files) {
      if (p.extension() != ".json" || p.string().find("_paper") != std::string::npos) continue;
      // As the engine reads it: a scene that extends another, merged over it.
      out.push_back(
          {p.filename().string(), p.parent_path().string(), nsf::read_scene_json(p.string())});
    }
  }
  std::ifstream in(root / "docs" / "SCENES.md");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string doc = ss.str();
  int k = 0;
  for (size_t at = doc.find("```json\n"); at != std::string::npos;
       at = doc.find("```json\n", at + 1)) {
    const size_t begin = at + 8, end = doc.find("```", begin);
    json j = json::parse(doc.substr(begin, end - begin), nullptr, false);
    if (j.is_object() && j.contains("simulation"))
      out.push_back(
          {"SCENES.md snippet " + std::to_string(k++), (root / "scenes" / "examples").string(), j});
  }
  return out;
}

// `objects[0].material.E`-style paths of the leaves of `v`, for --set overrides.
void leaf_paths(const json& v, const std::string& here, std::vector<std::string>& out) {
  if (v.is_object()) {
    for (auto it = v.begin(); it != v.end(); ++it)
      leaf_paths(it.value(), here.empty() ? it.key() : here + "." + it.key(), out);
  } else if (v.is_array()) {
    for (size_t i = 0; i < v.size(); ++i)
      leaf_paths(v[i], here + "[" + std::to_string(i) + "]", out);
  } else {
    out.push_back(here);
  }
}

// What a command does with a scene file: read it (overrides applied), check the sweep, build.
void read_and_build(const std::string& path, const std::vector<std::string>& overrides,
                    const std::string& base_dir) {
  const json j = nsf::read_scene_json(path, overrides);
  if (j.is_object() && j.contains("sweep")) nsf::parse_sweep(j.at("sweep"), j);
  nsf::build_scene(j, base_dir);
}

// The harness itself: each way a case can end is told apart, and a hang is cut off.
TEST(FuzzHarness, TellsCrashesHangsAndOtherExceptionsFromNamedErrors) {
  EXPECT_EQ(run_bounded([] {}, 10).outcome, Outcome::Accepted);
  const Result named = run_bounded([] { nsf::fail("scene: 'dx' is bad"); }, 10);
  EXPECT_EQ(named.outcome, Outcome::NamedError);
  EXPECT_EQ(named.detail, "scene: 'dx' is bad");
  EXPECT_EQ(run_bounded([] { throw std::out_of_range("stoul"); }, 10).outcome,
            Outcome::OtherException);
  EXPECT_EQ(run_bounded([] { ::raise(SIGSEGV); }, 10).outcome, Outcome::Crashed);
  EXPECT_EQ(run_bounded([] { std::abort(); }, 10).outcome, Outcome::Crashed);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(run_bounded(
                [] {
                  for (;;) ::pause();
                },
                0.5)
                .outcome,
            Outcome::TimedOut);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
  Tally t;
  t.add({Outcome::NamedError, "internal error: stoul"}, "case 0");
  t.add({Outcome::NamedError, "scene: 'dx' is bad"}, "case 1");
  EXPECT_EQ(t.failures.size(), 1u);
  EXPECT_EQ(t.named, 1);
}

TEST(FuzzScene, MutatedScenesAreReadOrRefusedWithANamedError) {
  const uint64_t seed = nsf::testing::fuzz::seed(20261126);
  const int cases = case_count(300);
  const char* only = std::getenv("NSF_FUZZ_ONLY");
  const double limit =
      std::getenv("NSF_FUZZ_CASE_SECONDS") ? std::atof(std::getenv("NSF_FUZZ_CASE_SECONDS")) : 20.0;
  std::cout << "fuzz seed " << seed << ", " << cases << " cases (NSF_FUZZ_SEED, NSF_FUZZ_CASES)\n";
  const std::vector<Seed> seeds = corpus();
  ASSERT_GE(seeds.size(), 10u);
  const fs::path dir =
      fs::path(::testing::TempDir()) / ("nsf_fuzz_scene_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  Tally tally;
  for (int i = 0; i < cases; ++i) {
    if (only && std::atoi(only) != i) continue;
    std::mt19937_64 rng(seed ^ (0x9e3779b97f4a7c15ull * uint64_t(i + 1)));
    const Seed& base = seeds[size_t(i) % seeds.size()];
    JsonMutator m(base.doc, rng);
    std::string what;
    const int steps = 1 + int(rng() % 3);
    for (int s = 0; s < steps; ++s) what += (s ? "; " : "") + m.mutate();
    std::string text = m.text();
    if (rng() % 4 == 0) {
      std::string bytes;
      ByteMutator b(rng);
      text = b.mutate(text, bytes);
      what += "; " + bytes;
    }
    std::vector<std::string> overrides;
    if (rng() % 5 == 0) {
      std::vector<std::string> paths;
      leaf_paths(base.doc, "", paths);
      std::string path = paths.empty() ? "name" : paths[rng() % paths.size()];
      const std::vector<std::string> value = {
          "1e999", "-1", "nan",    "[[[[1]]]]", "\"x\"",
          "{}",    "",   "1e-300", "true",      "[99999999999999999999]"};
      const std::vector<std::string> tail = {
          "", "[99999999999999999999]", "[-1]", ".", "[]", ".nope", "[0][0]"};
      path += tail[rng() % tail.size()];
      overrides.push_back(path + "=" + value[rng() % value.size()]);
      what += "; --set " + overrides.back();
    }
    const fs::path file = dir / ("case_" + std::to_string(i) + ".json");
    std::ofstream(file, std::ios::binary) << text;
    const std::string description = "case " + std::to_string(i) + " (" + base.name + ": " + what +
                                    ", file " + file.string() + ")";
    const Result r =
        run_bounded([&] { read_and_build(file.string(), overrides, base.dir); }, limit);
    if (std::getenv("NSF_FUZZ_VERBOSE"))
      std::cout << description << ": " << outcome_name(r.outcome) << ": " << r.detail << "\n";
    const size_t before = tally.failures.size();
    tally.add(r, description);
    if (tally.failures.size() == before) fs::remove(file);  // kept only to replay a failure
  }
  tally.report(seed, dir.string());
  EXPECT_GT(tally.accepted, 0);
}

}  // namespace
