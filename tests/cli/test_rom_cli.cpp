// `nsf rom` and `nsf demo` run as a user runs them, on the tiny scene's trained models
// (rom_end_to_end.h): the summary and the JSON row, the written run, the paper's baselines, threads
// and -q, and bad options.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cli_child.h"
#include "cli_runner.h"
#include "io/run_reader.h"
#include "nn/dataset.h"
#include "nn/model/neural_model.h"
#include "rom_end_to_end.h"

namespace fs = std::filesystem;
using nsf::testing::kTinyScene;
using nsf::testing::RomEndToEnd;
using nsf::testing::written_latents;
using ::testing::HasSubstr;
using ::testing::Not;

namespace {

// `nsf rom MODEL` on the tiny scene at `mu` with `flags`, against `truth`, without full order:
// the JSON row it writes to `row`.
nlohmann::json rom_row(const std::string& model, const std::string& truth, double mu,
                       const std::string& row, const std::string& flags) {
  const auto r = nsf::testing::run_cli(
      "rom '" + model + "' '" + kTinyScene + "' --mu " + std::to_string(mu) + " --truth '" + truth +
      "' --no-full-order -q --threads 2 " + flags + " --json '" + row + "'");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return nlohmann::json::parse(nsf::testing::read_text(row));
}

// The paper's baselines as a user runs them, through the command line: CROM's stress (τ from
// g's deformation gradient through the material, no l) and the first-order Taylor inversion.
TEST_F(RomEndToEnd, CromBaselineAndTaylorVariantRun) {
  const auto run = [&](const std::string& flag) {
    return rom_row(model(), truth(), test_mu(), (root_ / "baseline_row.json").string(), flag);
  };
  const nlohmann::json crom = run("--crom");
  EXPECT_EQ(crom.at("field_sources"),
            "x from g, tau from dg/dX through the material (CROM), C = 0");
  // It runs and stays near the others on this scene (4.0 % when the bound was set); a run that
  // diverged or froze does not.
  EXPECT_GT(crom.at("delta").get<double>(), 0.0);
  EXPECT_LT(crom.at("delta").get<double>(), 0.08);
  EXPECT_LT(run("--taylor").at("delta").get<double>(), 0.1);
}

// `nsf rom --guard`: the run goes through the runtime's step guard and its row says so. On a
// healthy run the guard redoes nothing and changes nothing: δ to the bit of the bare stepper's.
TEST_F(RomEndToEnd, CliGuardRunsTheStepGuardAndItsRowSaysSo) {
  const auto run = [&](const std::string& flag) {
    return rom_row(model(), truth(), test_mu(), (root_ / "guard_row.json").string(), flag);
  };
  const nlohmann::json bare = run(""), guarded = run("--guard");
  EXPECT_FALSE(bare.at("guarded").get<bool>());
  EXPECT_TRUE(guarded.at("guarded").get<bool>());
  EXPECT_EQ(guarded.at("recoveries").get<long>(), 0);
  EXPECT_EQ(guarded.at("delta").get<double>(), bare.at("delta").get<double>());
}

TEST_F(RomEndToEnd, CliWritesARunAndPrintsTheSummary) {
  const std::string out = (root_ / "rom.h5").string();
  const auto r = nsf::testing::run_cli("rom '" + model() + "' '" + kTinyScene +
                                       "' --mu 1.0 --threads 2 --out '" + out + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("speed-up"));
  EXPECT_THAT(r.output, HasSubstr("delta (eq. 11)"));
  EXPECT_THAT(r.output, HasSubstr("gamma"));
  EXPECT_THAT(r.output, HasSubstr("tau from h, C from l"));
  EXPECT_THAT(r.output, HasSubstr("stress error"));
  EXPECT_THAT(r.output, HasSubstr("from the training runs' latents on average"));
  EXPECT_THAT(r.output, HasSubstr("(no latent prior)"));
  const nsf::RunReader run(out);
  EXPECT_EQ(run.frame_count(), 13u);
  EXPECT_EQ(run.attribute_int("rom"), 1);
  // Provenance a reader elsewhere can use: the model's absolute path, and what μ is.
  EXPECT_EQ(run.attribute_string("rom_model"), fs::absolute(model()).lexically_normal().string());
  EXPECT_EQ(run.attribute_string("sweep_parameter"),
            nsf::RunReader(truth()).attribute_string("sweep_parameter"));
  EXPECT_FALSE(fs::exists(out + ".tmp"));
  // The latent trajectory beside the frames: one row of r = 4 per written frame.
  const std::vector<nsf::Latent> z = written_latents(out);
  ASSERT_EQ(z.size(), 13u);
  for (const nsf::Latent& row : z) EXPECT_EQ(row.size(), 4);
  const std::string row = (root_ / "rom_row.json").string();
  const auto held = nsf::testing::run_cli("rom '" + model() + "' '" + kTinyScene +
                                          "' --mu 1.0 --threads 2 --no-full-order --truth '" +
                                          truth() + "' --latent-prior 0.002 --json '" + row + "'");
  ASSERT_EQ(held.exit_code, 0) << held.output;
  EXPECT_THAT(held.output, HasSubstr("(latent prior, epsilon = 2 mm from the command line)"));
  // --json: the printed summary as a docs/results row.
  std::ifstream in(row);
  const nlohmann::json j = nlohmann::json::parse(in);
  char printed[64];
  std::snprintf(printed, sizeof printed, "%.3f%%", 100 * j.at("delta").get<double>());
  EXPECT_THAT(held.output, HasSubstr(printed));
  EXPECT_EQ(j.at("latent_prior").get<double>(), 0.002);
  EXPECT_EQ(j.at("field_sources").get<std::string>(), "x from g, tau from h, C from l");
  const auto bad = nsf::testing::run_cli("rom '" + model() + "' '" + kTinyScene +
                                         "' --mu 1.0 --no-full-order --latent-prior -1");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_THAT(bad.output, HasSubstr("--latent-prior"));
}

// The baselines beside the ROM (rom/eval/baselines.h; issue #25 point 4): `nsf rom --baselines DATA
// --coarse-factor k` prints look-up, interpolation and the coarse engine, and its JSON row holds
// them under the keys docs/results uses; bad baseline inputs stop the run before it starts.
TEST_F(RomEndToEnd, BaselinesSitBesideTheRomInItsSummaryAndRow) {
  const std::string row = (root_ / "baselines_row.json").string();
  const std::string data = (root_ / "data").string();
  const auto r = nsf::testing::run_cli("rom '" + basis_model() + "' '" + kTinyScene +
                                       "' --mu 1.0 -j 2 -q --baselines '" + data +
                                       "' --coarse-factor 1.5 --json '" + row + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(row);
  const nlohmann::json j = nlohmann::json::parse(in);
  for (const char* key : {"lookup_delta", "interp_delta", "coarse_delta", "coarse_speedup"}) {
    ASSERT_TRUE(j.contains(key)) << key;
    EXPECT_GT(j.at(key).get<double>(), 0) << key;
  }
  char printed[96];
  std::snprintf(printed, sizeof printed, "played back: %.3f%%",
                100 * j.at("lookup_delta").get<double>());
  EXPECT_THAT(r.output, HasSubstr(printed));
  std::snprintf(printed, sizeof printed, ": %.3f%%", 100 * j.at("interp_delta").get<double>());
  EXPECT_THAT(r.output, HasSubstr(printed));
  std::snprintf(printed, sizeof printed, "speed-up %.2fx against full order",
                j.at("coarse_speedup").get<double>());
  EXPECT_THAT(r.output, HasSubstr(printed));
  EXPECT_EQ(j.at("coarse_scene").get<std::string>(), "rom_tiny at 1.5x dx");
  // The sweep's training runs lie at 0.5, 0.833, 1.167, 1.5: μ = 1 sits between the middle two.
  const nsf::Dataset d(data);
  std::vector<double> mus;
  for (const auto& s : d.train()) mus.push_back(s.mu);
  std::sort(mus.begin(), mus.end());
  EXPECT_EQ(j.at("interp_mu").at(0).get<double>(), mus[1]);
  EXPECT_EQ(j.at("interp_mu").at(1).get<double>(), mus[2]);
  EXPECT_FALSE(j.at("interp_extrapolated").get<bool>());

  // A missing dataset or coarse scene stops the run before it starts, naming the path.
  const std::pair<std::string, std::string> bad_inputs[] = {
      {"--baselines", (root_ / "nothing").string()}, {"--coarse", (root_ / "none.json").string()}};
  for (const auto& [option, path] : bad_inputs) {
    const auto bad = nsf::testing::run_cli("rom '" + basis_model() + "' '" + kTinyScene +
                                           "' --mu 1.0 -q " + option + " '" + path + "'");
    EXPECT_NE(bad.exit_code, 0) << option;
    EXPECT_THAT(bad.output, HasSubstr(path));
    EXPECT_THAT(bad.output, Not(HasSubstr("reduced order:"))) << option;
  }
}

// A model from before nsf kept its training family learns it from its dataset (`nsf upgrade
// --data`, which refuses another dataset), and `nsf rom` then says when a scene leaves it;
// `--profile` picks the scene's settings whatever the family says.
TEST_F(RomEndToEnd, UpgradeRecordsTheFamilyAndRomSaysWhenASceneLeavesIt) {
  const std::string m = (root_ / "family.nsf").string(), data = (root_ / "data").string();
  fs::copy_file(basis_model(), m, fs::copy_options::overwrite_existing);
  {  // as an older nsf wrote it: no family
    nsf::NeuralModel old = nsf::NeuralModel::load(m);
    old.training_box.scene = nsf::SceneFamily();
    old.save(m);
  }
  const std::string rom = "rom '" + m + "' '" + kTinyScene + "' --mu 1.0 -j 2 --no-full-order ";
  const std::string lower = "--set 'colliders[0].point=[0,0.07,0]' ";
  auto r = nsf::testing::run_cli(rom + lower);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, Not(HasSubstr("training family")));

  r = nsf::testing::run_cli("upgrade '" + m + "' --data '" + data + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(nsf::NeuralModel::load(m).training_box.scene.runs(),
            int(nsf::Dataset(data).train().size()));
  r = nsf::testing::run_cli(rom);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, Not(HasSubstr("training family")));
  r = nsf::testing::run_cli(rom + lower);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("outside the model's training family (/colliders/0/point/1"));
  const std::string unseen = R"(--set 'rom.unseen={"samples": 30}' )";
  r = nsf::testing::run_cli(rom + lower + unseen + "--profile family");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("on the family's settings as asked"));
  EXPECT_THAT(r.output, Not(HasSubstr("|S| = 30")));
  r = nsf::testing::run_cli(rom + unseen + "--profile unseen");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("|S| = 30"));
  r = nsf::testing::run_cli(rom + "--profile sideways");
  EXPECT_EQ(r.exit_code, 2) << r.output;

  // Another dataset of the scene (here a part of this one) is refused, and the file kept.
  const std::string before = nsf::testing::read_text(m);
  const fs::path other = root_ / "other_data";
  fs::create_directories(other);
  for (const auto& e : fs::directory_iterator(data))
    if (e.path().filename().string().rfind("train_0", 0) == 0 ||
        e.path().filename().string().rfind("test_", 0) == 0)
      fs::copy_file(e.path(), other / e.path().filename(), fs::copy_options::overwrite_existing);
  r = nsf::testing::run_cli("upgrade '" + m + "' --data '" + other.string() + "'");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_THAT(r.output, HasSubstr(other.string()));
  EXPECT_EQ(nsf::testing::read_text(m), before);
}

// `nsf demo` end to end on the tiny scene, reusing the fixture's dataset and basis model: its
// summary row (out/demo.json, and with --docs DOCS/results/demo.json, the one README quotes)
// parses and holds the δ and speed-up the summary printed (issue #25 point 6).
TEST_F(RomEndToEnd, DemoWritesTheRowItsSummaryPrints) {
  const fs::path out = root_ / "demo", docs = root_ / "docs";
  const auto r = nsf::testing::run_cli(
      "demo --scene '" + kTinyScene + "' --data '" + (root_ / "data").string() + "' --model '" +
      basis_model() + "' --out '" + out.string() + "' --docs '" + docs.string() + "' -j 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const fs::path& row : {out / "demo.json", docs / "results" / "demo.json"}) {
    std::ifstream in(row);
    ASSERT_TRUE(in) << row;
    const nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_EQ(j.at("label").get<std::string>(), "demo");
    char delta[64], speedup[64];
    std::snprintf(delta, sizeof delta, "%.3f%%", 100 * j.at("delta").get<double>());
    std::snprintf(speedup, sizeof speedup, "%.2fx", j.at("speedup").get<double>());
    EXPECT_THAT(r.output, HasSubstr(delta)) << row;
    EXPECT_THAT(r.output, HasSubstr(speedup)) << row;
    EXPECT_GT(j.at("speedup").get<double>(), 0);
    EXPECT_EQ(j.at("model_file").get<std::string>(), basis_model());
  }
  EXPECT_TRUE(fs::exists(docs / "results" / "demo.png"));
}

// Threads default to all cores (OMP_NUM_THREADS where set) for both engines, as in every other
// command, and the JSON row records the count in use; -q drops the progress lines (issue #28,
// item 18: the default was 2 and rom had no -q).
TEST_F(RomEndToEnd, CliUsesAllCoresByDefaultAndQuietDropsTheProgressLines) {
  const std::string row = (root_ / "rom_threads.json").string();
  const std::string args =
      "rom '" + model() + "' '" + kTinyScene + "' --mu 1.0 --json '" + row + "'";
  std::string out;
  ASSERT_EQ(nsf::testing::run_cli(args + " -q", out, "OMP_NUM_THREADS=3"), 0) << out;
  EXPECT_THAT(out, Not(HasSubstr("done in"))) << out;
  EXPECT_THAT(out, HasSubstr("speed-up"));
  std::ifstream in(row);
  EXPECT_EQ(nlohmann::json::parse(in).at("threads").get<int>(), 3);
  ASSERT_EQ(nsf::testing::run_cli(args + " -j 1", out), 0) << out;
  EXPECT_THAT(out, HasSubstr("reduced order 12/12 frames done in")) << out;
  std::ifstream again(row);
  EXPECT_EQ(nlohmann::json::parse(again).at("threads").get<int>(), 1);
}

}  // namespace
