// A scene's "train" section (nn/train_section.h): the training recipe, what the command line
// keeps, and the errors that name the key at fault.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/pipeline.h"
#include "core/error.h"
#include "error_matchers.h"
#include "nn/train_section.h"
#include "rom/calibration/calibration_recipe.h"
#include "rom/calibration/latent_prior_calibration.h"

namespace nsf {
namespace {

using nlohmann::json;

// Parses `train` expecting an nsf::Error whose message contains every needle.
void expect_rejected(const json& train, std::initializer_list<std::string> needles) {
  SCOPED_TRACE(train.dump());
  nsf::testing::expect_error([&] { parse_train_section(train); }, needles);
}

TEST(TrainSection, SetsWhatTheCommandLineLeavesOpen) {
  const TrainSection t =
      parse_train_section(json::parse(R"({"steps": [34000, 1500, 1500], "widths": [192, 128, 128],
                      "encoder_max_length": 1024, "frames_per_batch": [16, 4, 4],
                      "particles_per_frame": [128, 512, 512]})"));
  TrainPlan cli;
  cli.steps = {6000, 4000, 4000};
  cli.widths = {0, 96, 96};
  const TrainPlan scene = with_train_section(cli, t, {});
  EXPECT_EQ(scene.steps, (std::array<long, 3>{34000, 1500, 1500}));
  EXPECT_EQ(scene.widths, (std::array<int, 3>{192, 128, 128}));
  EXPECT_EQ(scene.encoder_max_length, 1024);
  EXPECT_EQ(scene.frames_per_batch, (std::array<int, 3>{16, 4, 4}));
  EXPECT_EQ(scene.particles_per_frame, (std::array<int, 3>{128, 512, 512}));
  GivenOnCommandLine flags;  // --steps and every width on the command line win
  flags.steps = true;
  flags.widths = {true, true, true};
  const TrainPlan given = with_train_section(cli, t, flags);
  EXPECT_EQ(given.steps, cli.steps);
  EXPECT_EQ(given.widths, cli.widths);
  EXPECT_EQ(given.encoder_max_length, 1024);
  EXPECT_EQ(recipe_taken(t, flags),
            "encoder_max_length 1024; frames_per_batch 16,4,4; particles_per_frame 128,512,512");
  // One width and the batches given (nsf train --width-h, --frames-per-batch, ...): the
  // recipe fills in the rest.
  GivenOnCommandLine some;
  some.widths = {false, true, false};
  some.encoder_max_length = some.frames_per_batch = some.particles_per_frame = true;
  const TrainPlan mixed = with_train_section(cli, t, some);
  EXPECT_EQ(mixed.widths, (std::array<int, 3>{192, 96, 128}));
  EXPECT_EQ(mixed.encoder_max_length, 0);
  EXPECT_EQ(mixed.frames_per_batch, cli.frames_per_batch);
  EXPECT_EQ(mixed.particles_per_frame, cli.particles_per_frame);
  EXPECT_EQ(recipe_taken(t, some), "steps 34000,1500,1500; width g 192; width l 128");
  // Keys left out keep the command's values.
  const TrainPlan partial =
      with_train_section(cli, parse_train_section(json::parse(R"({"steps": [1, 2, 3]})")), {});
  EXPECT_EQ(partial.steps, (std::array<long, 3>{1, 2, 3}));
  EXPECT_EQ(partial.widths, cli.widths);
  EXPECT_EQ(partial.encoder_max_length, 0);
  EXPECT_EQ(partial.frames_per_batch, (std::array<int, 3>{0, 0, 0}));
}

// r: the scene's latent dimension in place of Table 1's, unless the command line gives -r.
TEST(TrainSection, SetsTheLatentDimensionUnlessTheCommandLineGivesOne) {
  const TrainSection t = parse_train_section(json::parse(R"({"latent_dim": 8})"));
  EXPECT_EQ(t.latent_dim, 8);
  TrainPlan cli;
  EXPECT_EQ(with_train_section(cli, t, {}).latent_dim, 8);
  EXPECT_EQ(recipe_taken(t, {}), "r 8");
  GivenOnCommandLine r;
  r.latent_dim = true;
  EXPECT_EQ(with_train_section(cli, t, r).latent_dim, 0);
  EXPECT_EQ(recipe_taken(t, r), "");
  EXPECT_EQ(parse_train_section(json::object()).latent_dim, 0);
  // What nsf report and nsf demo train with (app::apply_plan): r from the plan, else Table 1's.
  TrainConfig config;
  config.net.latent_dim = 5;
  app::apply_plan(with_train_section(cli, t, {}), config);
  EXPECT_EQ(config.net.latent_dim, 8);
  config.net.latent_dim = 5;
  app::apply_plan(with_train_section(cli, t, r), config);
  EXPECT_EQ(config.net.latent_dim, 5);
}

// The decoder family: a scene whose ROM runs better on the paper's MLP fields says so, and the
// command line's --decoder wins.
TEST(TrainSection, SetsTheDecoderFamilyUnlessTheCommandLineGivesOne) {
  const TrainSection t = parse_train_section(json::parse(R"({"decoder": "mlp"})"));
  EXPECT_EQ(t.decoder, "mlp");
  TrainPlan cli;
  EXPECT_EQ(with_train_section(cli, t, {}).decoder, "mlp");
  EXPECT_EQ(recipe_taken(t, {}), "decoder mlp");
  GivenOnCommandLine d;
  d.decoder = true;
  cli.decoder = "basis";
  EXPECT_EQ(with_train_section(cli, t, d).decoder, "basis");
  EXPECT_EQ(recipe_taken(t, d), "");
  EXPECT_EQ(parse_train_section(json::object()).decoder, "");
  TrainConfig config;
  config.net.decoder = nsf::DecoderFamily::basis;
  app::apply_plan(with_train_section(TrainPlan(), t, {}), config);
  EXPECT_EQ(config.net.decoder, nsf::DecoderFamily::mlp);
}

// The encoder of a basis model: the recipe's unless the command line gives one, and never on
// an MLP model (--decoder mlp over a scene whose recipe names the modes encoder).
TEST(TrainSection, SetsABasisModelsEncoderUnlessTheCommandLineGivesOne) {
  const TrainSection t = parse_train_section(json::parse(R"({"encoder": "modes"})"));
  EXPECT_EQ(t.encoder, "modes");
  EXPECT_EQ(recipe_taken(t, {}), "encoder modes");
  TrainConfig config;
  app::apply_plan(with_train_section(TrainPlan(), t, {}), config);
  EXPECT_EQ(config.net.encoder, "modes");
  GivenOnCommandLine e;
  e.encoder = true;
  EXPECT_EQ(with_train_section(TrainPlan(), t, e).encoder, "");
  EXPECT_EQ(recipe_taken(t, e), "");
  TrainPlan mlp;
  mlp.decoder = "mlp";
  GivenOnCommandLine d;
  d.decoder = true;
  TrainConfig other;
  app::apply_plan(with_train_section(mlp, t, d), other);
  EXPECT_EQ(other.net.decoder, nsf::DecoderFamily::mlp);
  EXPECT_EQ(other.net.encoder, "network");
}

// `nsf report --decoder F`: the scene's own family keeps models/NAME.nsf and the plain rows; the
// other family gets a model and rows of its own, so it never overwrites the scene's.
TEST(TrainSection, ReportKeepsTheOtherFamilysModelAndRowsApart) {
  const auto scene = [](const char* name) {
    return (std::filesystem::path(NSF_SOURCE_DIR) / "scenes" / "paper" / name).string();
  };
  EXPECT_EQ(app::scene_decoder(scene("sand_paper.json")), "mlp");  // its recipe says so
  EXPECT_EQ(app::scene_decoder(scene("jelly_small.json")), "basis");
  for (const std::string asked : {"", "basis"}) {
    const app::DecoderRows own = app::decoder_rows("jelly_small", "basis", asked);
    EXPECT_EQ(own.model, "models/jelly_small.nsf");
    EXPECT_EQ(own.tag_suffix, "");
    EXPECT_EQ(own.label, "");
  }
  const app::DecoderRows mlp = app::decoder_rows("jelly_small", "basis", "mlp");
  EXPECT_EQ(mlp.model, "models/jelly_small_mlp.nsf");
  EXPECT_EQ(mlp.tag_suffix, "_mlp");
  EXPECT_EQ(mlp.label, "MLP fields");
  const app::DecoderRows bases = app::decoder_rows("sand_paper", "mlp", "basis");
  EXPECT_EQ(bases.model, "models/sand_paper_basis.nsf");
  EXPECT_EQ(bases.tag_suffix, "_basis");
  EXPECT_EQ(bases.label, "per-point bases");
  EXPECT_EQ(app::decoder_rows("sand_paper", "mlp", "mlp").model, "models/sand_paper.nsf");
}

TEST(TrainSection, NamesTheKeyAtFault) {
  expect_rejected({{"steps", {100, 0, 100}}}, {"train.steps[1]", "0"});
  expect_rejected({{"widths", {64, 64}}}, {"train.widths", "three"});
  expect_rejected({{"particles_per_frame", {128, -1, 512}}},
                  {"train.particles_per_frame[1]", "-1"});
  expect_rejected({{"encoder_max_length", 3}}, {"train.encoder_max_length", "3"});
  expect_rejected({{"epochs", 5}}, {"train.epochs"});
  expect_rejected({{"latent_dim", 0}}, {"train.latent_dim", "0"});
  expect_rejected({{"latent_dim", 2.5}}, {"train.latent_dim"});
  expect_rejected({{"decoder", "svd"}}, {"train.decoder", "\"mlp\" or \"basis\"", "svd"});
  expect_rejected({{"decoder", 1}}, {"train.decoder"});
  expect_rejected({{"encoder", "pca"}}, {"train.encoder", "\"network\" or \"modes\"", "pca"});
  expect_rejected(5, {"'train'"});
}

// "calibrate": how a model of the scene is calibrated where nsf calibrate's command line does not
// say (and how nsf train, report and demo calibrate what they train).
// The ROM's part of the section (rom/calibration/calibration_recipe.h); the trainer's parse
// takes the key and leaves it to the ROM.
TEST(TrainSection, TakesACalibrationRecipe) {
  const json one = json::parse(
      R"({"calibrate": {"grid": [0, 0.01], "dt_ratios": [4, 10], "set": ["rom.quadrature=1"]}})");
  parse_train_section(one);
  const std::vector<nsf::CalibrationRecipe> t = nsf::parse_calibration_recipes(one);
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0].grid, (std::vector<double>{0, 0.01}));
  EXPECT_EQ(t[0].dt_ratios, (std::vector<double>{4, 10}));
  EXPECT_EQ(t[0].set, (std::vector<std::string>{"rom.quadrature=1"}));
  EXPECT_TRUE(nsf::parse_calibration_recipes(json::object()).empty());
  // A list: one recipe per kind of run the model keeps a calibration of, made in turn.
  const std::vector<nsf::CalibrationRecipe> two = nsf::parse_calibration_recipes(json::parse(
      R"({"calibrate": [{"grid": [0]}, {"dt_ratios": [1, 1.4], "set": ["rom.fields.stress=tracked"]}]})"));
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[0].grid, (std::vector<double>{0}));
  EXPECT_EQ(two[1].set, (std::vector<std::string>{"rom.fields.stress=tracked"}));

  const auto app = [](const char* calibrate) {
    return json::parse(std::string(R"({"calibrate": )") + calibrate + "}");
  };
  const auto expect_rejected = [](const json& train, std::initializer_list<std::string> needles) {
    SCOPED_TRACE(train.dump());
    nsf::testing::expect_error([&] { nsf::parse_calibration_recipes(train); }, needles);
  };
  expect_rejected(app(R"({"dt_ratios": [4, 2]})"), {"train.calibrate.dt_ratios[1]", "ascending"});
  expect_rejected(app(R"({"dt_ratios": [0]})"), {"train.calibrate.dt_ratios[0]", "positive"});
  expect_rejected(app(R"({"grid": [-0.1]})"), {"train.calibrate.grid[0]", "non-negative"});
  expect_rejected(app(R"({"grid": []})"), {"train.calibrate.grid", "non-empty"});
  expect_rejected(app(R"({"set": ["rom.quadrature"]})"), {"train.calibrate.set[0]", "KEY=VALUE"});
  expect_rejected(app(R"({"tolerance": 2})"), {"train.calibrate.tolerance"});
  expect_rejected(app("3"), {"train.calibrate"});
  expect_rejected(app("[]"), {"train.calibrate", "non-empty list"});
  expect_rejected(app(R"([{"grid": [0]}, {"grid": [-1]}])"), {"train.calibrate[1].grid[0]"});
  // The unseen profile's recipe: measured on perturbed cases, "draws" of them.
  const std::vector<nsf::CalibrationRecipe> unseen =
      nsf::parse_calibration_recipes(app(R"({"unseen": true, "draws": 6, "grid": [0, 0.001]})"));
  ASSERT_EQ(unseen.size(), 1u);
  EXPECT_TRUE(unseen[0].unseen);
  EXPECT_EQ(unseen[0].draws, 6);
  EXPECT_FALSE(nsf::parse_calibration_recipes(app(R"({"grid": [0]})"))[0].unseen);
  expect_rejected(app(R"({"unseen": 1})"), {"train.calibrate.unseen", "true or false"});
  expect_rejected(app(R"({"draws": 4})"), {"train.calibrate.draws", "\"unseen\": true"});
  expect_rejected(app(R"({"unseen": true, "draws": 0})"), {"train.calibrate.draws"});
}

// The recipe fills what nsf calibrate's command line left open, and only that.
TEST(TrainSection, CalibrationRecipeFillsWhatTheCommandLineLeftOpen) {
  const json scene = json::parse(R"({
    "name": "s", "simulation": {"dx": 0.125, "dt": 1e-3, "frames": 2, "substeps": 2},
    "objects": [{"shape": {"type": "box", "min": [0.375, 0.375, 0.375], "max": [0.625, 0.625, 0.625]},
                 "material": {"type": "fixed_corotated", "E": 1000, "nu": 0.3}}],
    "train": {"calibrate": {"grid": [0.001], "dt_ratios": [1, 2], "set": ["rom.quadrature=1"]}}
  })");
  const std::filesystem::path p = std::filesystem::path(::testing::TempDir()) / "recipe.json";
  std::ofstream(p) << scene.dump();
  CalibrationOptions o;
  o.scene_path = p.string();
  o.quiet = true;
  o.overrides = {"rom.samples=9"};
  apply_calibration_recipe(o, {});
  EXPECT_EQ(o.grid, (std::vector<double>{0.001}));
  EXPECT_EQ(o.dt_ratios, (std::vector<double>{1, 2}));
  EXPECT_EQ(o.overrides, (std::vector<std::string>{"rom.samples=9", "rom.quadrature=1"}));
  CalibrationOptions given;
  given.scene_path = p.string();
  given.quiet = true;
  given.grid = {0.5};
  given.overrides = {"rom.samples=9"};
  apply_calibration_recipe(given, {true, false, true});
  EXPECT_EQ(given.grid, (std::vector<double>{0.5}));
  EXPECT_EQ(given.dt_ratios, (std::vector<double>{1, 2}));
  EXPECT_EQ(given.overrides, (std::vector<std::string>{"rom.samples=9"}));
  EXPECT_FALSE(given.unseen);
  // An unseen recipe: the perturbed cases and their count, unless the command line gave its own.
  json with_unseen = scene;
  with_unseen["train"]["calibrate"] = json::parse(R"({"unseen": true, "draws": 3})");
  std::ofstream(p) << with_unseen.dump();
  CalibrationOptions u;
  u.scene_path = p.string();
  u.quiet = true;
  apply_calibration_recipe(u, {});
  EXPECT_TRUE(u.unseen);
  EXPECT_EQ(u.draws, 3);
  CalibrationOptions u_given;
  u_given.scene_path = p.string();
  u_given.quiet = true;
  u_given.draws = 8;
  apply_calibration_recipe(u_given, {false, false, false, false, true});
  EXPECT_TRUE(u_given.unseen);
  EXPECT_EQ(u_given.draws, 8);
}

// A list of recipes: nsf calibrate --recipe N takes the Nth; each kind of run reads the scene's
// own rom settings for it (the tracked state its "tracked" object), which the recipe's --set
// decides.
TEST(TrainSection, EachRecipeOfAListCalibratesTheKindOfRunItsSetMakes) {
  json scene = json::parse(R"({
    "name": "s", "simulation": {"dx": 0.125, "dt": 1e-3, "frames": 2, "substeps": 2},
    "objects": [{"shape": {"type": "box", "min": [0.375, 0.375, 0.375], "max": [0.625, 0.625, 0.625]},
                 "material": {"type": "fixed_corotated", "E": 1000, "nu": 0.3}}],
    "rom": {"latent_prior": 0, "fields": {}, "tracked": {"latent_prior": 0.002, "dt_ratio": 1.5}},
    "train": {"calibrate": [{"grid": [0.001]},
                            {"grid": [0.003], "set": ["rom.fields.stress=tracked"]}]}
  })");
  const std::filesystem::path p = std::filesystem::path(::testing::TempDir()) / "recipes.json";
  std::ofstream(p) << scene.dump();
  EXPECT_EQ(calibration_recipes(p.string()), 2u);
  CalibrationOptions first, second, none;
  first.scene_path = second.scene_path = none.scene_path = p.string();
  first.quiet = second.quiet = none.quiet = true;
  apply_calibration_recipe(first, {}, 0);
  apply_calibration_recipe(second, {}, 1);
  EXPECT_EQ(first.grid, (std::vector<double>{0.001}));
  EXPECT_EQ(second.grid, (std::vector<double>{0.003}));
  const SceneRomSettings plain = scene_rom_settings(first, nsf::DecoderFamily::basis);
  EXPECT_FALSE(plain.tracked);
  EXPECT_EQ(plain.latent_prior, 0.0);
  EXPECT_FALSE(plain.dt_ratio);
  const SceneRomSettings tracked = scene_rom_settings(second, nsf::DecoderFamily::basis);
  EXPECT_TRUE(tracked.tracked);
  EXPECT_EQ(tracked.latent_prior, 0.002);
  EXPECT_EQ(tracked.dt_ratio, 1.5);
  nsf::testing::expect_error([&] { apply_calibration_recipe(none, {}, 2); },
                             {"gives 2 calibration recipes", "no recipe 3"});
}

// Every "train" snippet in docs/SCENES.md parses (tests/unit/data/test_scene.cpp checks the other
// kinds).
TEST(TrainSection, DocsSnippetsParse) {
  std::ifstream in(std::filesystem::path(NSF_SOURCE_DIR) / "docs" / "SCENES.md");
  ASSERT_TRUE(in);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string doc = ss.str();
  size_t checked = 0;
  for (size_t at = doc.find("```json\n"); at != std::string::npos;
       at = doc.find("```json\n", at + 1)) {
    const size_t begin = at + 8, end = doc.find("```", begin);
    const std::string text = doc.substr(begin, end - begin);
    json j = json::parse(text, nullptr, false);
    if (j.is_discarded()) j = json::parse("{" + text + "}");  // a "key": value fragment
    if (!j.contains("train")) continue;
    SCOPED_TRACE(text);
    EXPECT_NO_THROW(parse_train_section(j["train"]));
    ++checked;
  }
  EXPECT_GE(checked, 1u);
}

}  // namespace
}  // namespace nsf
