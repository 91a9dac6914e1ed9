// A scene's "rom" section (rom/setup/rom_section.h): the sample particles, the ROM's time step, its
// latent prior, quadrature, Gauss–Newton cap and field sources, and the errors that name the key
// at fault.
#include <gtest/gtest.h>

#include <map>

#include "core/error.h"
#include "error_matchers.h"
#include "rom/setup/rom_section.h"

namespace nsf {
namespace {

using nlohmann::json;

// Parses `rom` expecting an nsf::Error whose message contains every needle.
void expect_rejected(const json& rom, std::initializer_list<std::string> needles) {
  SCOPED_TRACE(rom.dump());
  nsf::testing::expect_error([&] { parse_rom_section(rom); }, needles);
}

TEST(RomSection, TakesSamplesAndATimeStepRatio) {
  const RomSection r = parse_rom_section(json::parse(R"({"samples": 200, "dt_ratio": 4})"));
  EXPECT_EQ(r.sampling.count, 200);
  ASSERT_TRUE(r.dt_ratio.has_value());
  EXPECT_DOUBLE_EQ(*r.dt_ratio, 4.0);
  EXPECT_FALSE(parse_rom_section(json::parse(R"({"samples": 200})")).dt_ratio.has_value());
  EXPECT_EQ(parse_rom_section(json()).sampling.count, SamplingSpec().count);  // no section

  expect_rejected({{"samples", 50}, {"dt_ratio", 0}}, {"rom.dt_ratio", "positive"});
  expect_rejected({{"dt_ratio", "fast"}}, {"rom.dt_ratio", "fast", "\"cfl\""});
  EXPECT_EQ(parse_rom_section(json{{"dt_ratio", "cfl"}}).dt_ratio, nsf::RomOptions::kDtRatioAtCfl);
  // The unknown key, and the known ones.
  expect_rejected({{"samples", 50}, {"step", 2}}, {"rom.step", "dt_ratio"});
  expect_rejected(5, {"'rom'"});
}

// The keys an unknown one's message lists are the parser's own: each, with a valid value, is read
// (a key listed but not read would reach the sampling's parser and be refused there).
TEST(RomSection, TheKnownKeysAnUnknownOneListsAreEachRead) {
  const std::string message = nsf::testing::error_of([] {
    parse_rom_section(json{{"no_such_key", 1}});
  });
  const std::string head = "(known: ";
  const size_t at = message.find(head);
  ASSERT_NE(at, std::string::npos) << message;
  const std::string list = message.substr(at + head.size(), message.rfind(')') - at - head.size());
  const std::map<std::string, json> valid = {{"samples", 100},
                                             {"sampling", "random"},
                                             {"center", {0, 0, 0}},
                                             {"sigma", 0.1},
                                             {"seed", 1},
                                             {"schedule", json::array()},
                                             {"dt_ratio", 1},
                                             {"latent_prior", 0},
                                             {"quadrature", 1},
                                             {"gn_iterations", 3},
                                             {"gn_damping", 0},
                                             {"fields", json::object()},
                                             {"cfl", 0.5},
                                             {"grid", 1},
                                             {"rigid_frames", json::array()},
                                             {"profile", "auto"},
                                             {"tracked", json::object()},
                                             {"unseen", json::object()},
                                             {"mlp", json::object()},
                                             {"basis", json::object()}};
  json all = json::object();
  size_t listed = 0;
  for (size_t from = 0; from < list.size(); ++listed) {
    const size_t comma = list.find(", ", from);
    const std::string key =
        list.substr(from, comma == std::string::npos ? std::string::npos : comma - from);
    from = comma == std::string::npos ? list.size() : comma + 2;
    ASSERT_TRUE(valid.count(key)) << "a new key '" << key << "': give it a valid value here";
    EXPECT_NO_THROW(parse_rom_section(json{{key, valid.at(key)}})) << key;
    all[key] = valid.at(key);
  }
  EXPECT_EQ(listed, valid.size()) << list;
  EXPECT_NO_THROW(parse_rom_section(all));
}

// The cake's schedule: 700 samples, 400 from T/2 on. A smaller initial count (--samples 250)
// is never raised by it: S only shrinks.
TEST(RomSection, ASampleScheduleOnlyShrinksS) {
  SamplingSpec s = parse_rom_section(json::parse(R"({"samples": 700, "sampling": "cluster",
      "sigma": 0.04, "schedule": [{"fraction": 0.5, "samples": 400}]})"))
                       .sampling;
  EXPECT_EQ(nsf::sample_count_at(s, 0.0, 1.0), 700);
  EXPECT_EQ(nsf::sample_count_at(s, 0.49, 1.0), 700);
  EXPECT_EQ(nsf::sample_count_at(s, 0.5, 1.0), 400);
  s.count = 250;  // as --samples 250 sets it
  EXPECT_EQ(nsf::sample_count_at(s, 0.0, 1.0), 250);
  EXPECT_EQ(nsf::sample_count_at(s, 0.9, 1.0), 250);
  expect_rejected({{"samples", 300}, {"schedule", {{{"fraction", 0.5}, {"samples", 400}}}}},
                  {"rom.schedule", "400", "shrink"});
}

// A scene's measured ROM settings: quadrature, Gauss–Newton cap and field sources by name; each
// malformed one is rejected with its key.
TEST(RomSection, TakesQuadratureIterationsAndFieldSources) {
  const RomSection r = parse_rom_section(json::parse(
      R"({"samples": 100, "quadrature": 1, "gn_iterations": 2, "fields": {"affine": "none"}})"));
  EXPECT_EQ(r.sampling.count, 100);
  ASSERT_TRUE(r.quadrature && r.gn_iterations);
  EXPECT_EQ(*r.quadrature, 1);
  EXPECT_EQ(*r.gn_iterations, 2);
  EXPECT_EQ(r.fields.affine, "none");
  EXPECT_EQ(r.fields.stress, "");
  EXPECT_EQ(r.fields.velocity, "");
  EXPECT_FALSE(parse_rom_section(json::parse(R"({"samples": 200})")).quadrature.has_value());
  // The velocity's source (the elastic scenes' points carry their own), kept unless the options
  // name one.
  const RomSection v = parse_rom_section(json::parse(R"({"fields": {"velocity": "tracked"}})"));
  EXPECT_EQ(v.fields.velocity, "tracked");
  EXPECT_EQ(with_rom_section(RomOptions(), v).fields.velocity, "tracked");
  RomOptions given;
  given.fields.velocity = "latent";
  EXPECT_EQ(with_rom_section(given, v).fields.velocity, "latent");
  EXPECT_EQ(RomOptions().resolved_fields("basis").velocity, "latent");

  EXPECT_EQ(with_rom_section(RomOptions(), parse_rom_section(json{{"gn_damping", 0.01}}))
                .inversion.damping,
            0.01);
  EXPECT_EQ(with_rom_section(RomOptions(), parse_rom_section(json::object())).inversion.damping,
            0.0);
  expect_rejected({{"gn_damping", -1}}, {"rom.gn_damping", "non-negative"});
  expect_rejected({{"quadrature", 1.5}}, {"rom.quadrature", "whole number"});
  expect_rejected({{"gn_iterations", 0}}, {"rom.gn_iterations", "1 to 100"});
  // The tracked state's own CFL factor, in (0, 1].
  EXPECT_EQ(with_rom_section(RomOptions(), parse_rom_section(json{{"cfl", 0.85}})).cfl, 0.85);
  EXPECT_EQ(with_rom_section(RomOptions(), parse_rom_section(json::object())).cfl, 0.0);
  expect_rejected({{"cfl", 0}}, {"rom.cfl", "positive"});
  expect_rejected({{"cfl", 1.5}}, {"rom.cfl", "at most 1"});
  EXPECT_EQ(with_rom_section(RomOptions(), parse_rom_section(json{{"grid", 1.25}})).grid_factor,
            1.25);
  EXPECT_EQ(with_rom_section(RomOptions(), parse_rom_section(json::object())).grid_factor, 1.0);
  expect_rejected({{"grid", 0.5}}, {"rom.grid", "at least 1"});
  expect_rejected({{"grid", "coarse"}}, {"rom.grid", "positive"});
  // The objects that move in rigid frames of their own, in any order, each once.
  EXPECT_EQ(
      with_rom_section(RomOptions(), parse_rom_section(json::parse(R"({"rigid_frames": [2, 0]})")))
          .rigid_frames,
      std::vector<int>({0, 2}));
  EXPECT_TRUE(
      with_rom_section(RomOptions(), parse_rom_section(json::object())).rigid_frames.empty());
  expect_rejected({{"rigid_frames", 0}}, {"rom.rigid_frames", "list of distinct object indices"});
  expect_rejected({{"rigid_frames", {0, 0}}}, {"rom.rigid_frames", "distinct"});
  expect_rejected({{"rigid_frames", {-1}}}, {"rom.rigid_frames", "[-1]"});
  expect_rejected({{"rigid_frames", {"ball"}}}, {"rom.rigid_frames"});
  expect_rejected({{"fields", {{"affine", 3}}}}, {"rom.fields.affine", "name"});
  expect_rejected({{"fields", {{"density", "none"}}}},
                  {"rom.fields.density", "deformation, stress, affine, velocity"});
  // Sources that lost and were removed name their record.
  expect_rejected(
      {{"fields", {{"affine", "velocity"}}}},
      {"rom.fields.affine", "retired", "docs/experiments/2026-11-22-velocity-affine.md"});
  expect_rejected({{"fields", {{"stress", "tangent"}}}},
                  {"rom.fields.stress", "retired", "docs/experiments/2026-11-22-tangent-cache.md"});
}

// ε of the latent prior: the section's, else the model's calibration (≥ 0), else the options'.
TEST(RomSection, ALatentPriorOfItsOwnWinsOverTheModelsCalibration) {
  const RomSection none = parse_rom_section(json::parse(R"({"samples": 100})"));
  const RomSection own = parse_rom_section(json::parse(R"({"latent_prior": 0.002})"));
  RomOptions o;
  o.latent_prior = 0.5;  // what a caller had before the section
  EXPECT_EQ(with_rom_section(o, none).latent_prior, 0.5);
  EXPECT_EQ(with_rom_section(o, none, {0.0003}).latent_prior, 0.0003);
  EXPECT_EQ(with_rom_section(o, none, {0.0}).latent_prior, 0.0);  // calibrated to none
  EXPECT_EQ(with_rom_section(o, own, {0.0003}).latent_prior, 0.002);
  EXPECT_EQ(with_rom_section(o, own).latent_prior, 0.002);
}

// The ROM's step: the section's, else the model's calibration (> 0), else the options'.
// QDEIM's samples (issue #55) are read from the section like the other samplings; an unknown
// sampling is refused, naming the choices.
TEST(RomSection, TakesQdeimSampling) {
  const RomSection s = parse_rom_section(json::parse(R"({"sampling": "qdeim"})"));
  EXPECT_EQ(with_rom_section(RomOptions(), s).sampling.mode, "qdeim");
  expect_rejected(json::parse(R"({"sampling": "deim"})"), {"rom.sampling", "qdeim"});
}

TEST(RomSection, AStepOfItsOwnWinsOverTheModelsCalibration) {
  const RomSection none = parse_rom_section(json::parse(R"({"samples": 100})"));
  const RomSection own = parse_rom_section(json::parse(R"({"dt_ratio": 2})"));
  RomOptions o;
  o.dt_ratio = 1.5;
  EXPECT_EQ(with_rom_section(o, none).dt_ratio, 1.5);
  EXPECT_EQ(with_rom_section(o, none, {-1, 3}).dt_ratio, 3);
  EXPECT_EQ(with_rom_section(o, none, {0.001, -1}).dt_ratio, 1.5);  // a prior, but no step chosen
  EXPECT_EQ(with_rom_section(o, own, {-1, 3}).dt_ratio, 2);
}

// A family's object ("mlp", "basis") holds the settings a model of that decoder family reads,
// over the common ones; a null in it removes a common setting, so that the model's calibration
// speaks. The other family, and a section without one, read the common settings.
TEST(RomSection, EachDecoderFamilyReadsItsOwnSettingsOverTheCommonOnes) {
  const RomSection s = parse_rom_section(json::parse(R"({
    "samples": 200, "dt_ratio": 4, "latent_prior": 0.002, "fields": {"stress": "tracked"},
    "basis": {"samples": 500, "dt_ratio": null, "latent_prior": null, "fields": {"affine": "basis"}}
  })"));
  const RomSection& mlp = s.for_family(nsf::DecoderFamily::mlp);
  EXPECT_EQ(&mlp, &s);
  EXPECT_EQ(mlp.sampling.count, 200);
  EXPECT_EQ(mlp.dt_ratio, 4.0);
  const RomSection& basis = s.for_family(nsf::DecoderFamily::basis);
  EXPECT_EQ(basis.sampling.count, 500);
  EXPECT_FALSE(basis.dt_ratio);
  EXPECT_FALSE(basis.latent_prior);
  EXPECT_EQ(basis.fields.stress, "tracked");
  EXPECT_EQ(basis.fields.affine, "basis");
  EXPECT_EQ(with_rom_section(RomOptions(), basis, {0.01, 10}).dt_ratio, 10);
  EXPECT_EQ(with_rom_section(RomOptions(), basis, {0.01, 10}).latent_prior, 0.01);
  EXPECT_EQ(with_rom_section(RomOptions(), mlp, {0.01, 10}).dt_ratio, 4);
  const RomSettingSources basis_sources = rom_setting_sources(basis, {0.01, 10}, false, false);
  EXPECT_EQ(basis_sources.dt_ratio, "model");
  EXPECT_EQ(basis_sources.latent_prior, "model");
  const RomSettingSources mlp_sources = rom_setting_sources(mlp, {0.01, 10}, false, true);
  EXPECT_EQ(mlp_sources.dt_ratio, "command line");
  EXPECT_EQ(mlp_sources.latent_prior, "scene");
  const RomSection plain = parse_rom_section(json::parse(R"({"samples": 9})"));
  EXPECT_EQ(&plain.for_family(nsf::DecoderFamily::basis), &plain);

  // A --set of a common key that the family sets again does not reach the model: named.
  const json rom = json::parse(R"({"samples": 200, "basis": {"samples": 500, "dt_ratio": null}})");
  const std::vector<std::string> hidden = overrides_hidden_by(
      rom, "basis", {"rom.samples=1000", "rom.quadrature=2", "rom.dt_ratio=3", "simulation.dt=1"});
  ASSERT_EQ(hidden.size(), 2u);
  EXPECT_NE(hidden[0].find("rom.basis.samples = 500 wins"), std::string::npos) << hidden[0];
  EXPECT_NE(hidden[1].find("rom.basis.dt_ratio = null"), std::string::npos) << hidden[1];
  EXPECT_TRUE(overrides_hidden_by(rom, "mlp", {"rom.samples=1000"}).empty());

  expect_rejected(json::parse(R"({"basis": 3})"), {"rom.basis", "must be an object"});
  expect_rejected(json::parse(R"({"mlp": {"basis": {}}})"), {"rom.mlp.basis", "hold no basis"});
  expect_rejected(json::parse(R"({"basis": {"dt_ratio": -1}})"), {"rom.basis", "rom.dt_ratio"});
  expect_rejected(json::parse(R"({"mlp": {"frobnicate": 1}})"), {"rom.mlp", "frobnicate"});
}

// The "tracked" object holds what a run with the tracked state reads (its stress the points' own,
// chosen on the command line or by the section), over the family's settings; a run with the
// decoders' stress never sees it, and a null in it hands a setting to the model's calibration.
TEST(RomSection, ARunWithTheTrackedStateReadsTheTrackedSettings) {
  const RomSection s = parse_rom_section(json::parse(R"({
    "samples": 200, "latent_prior": 0, "quadrature": 1,
    "tracked": {"latent_prior": null, "dt_ratio": 1.4, "fields": {"affine": "tracked"}},
    "basis": {"samples": 500, "tracked": {"samples": 300}}
  })"));
  EXPECT_FALSE(s.tracks_stress(nsf::DecoderFamily::mlp));
  EXPECT_TRUE(s.tracks_stress(nsf::DecoderFamily::mlp, "tracked"));
  EXPECT_EQ(&s.for_run(nsf::DecoderFamily::mlp), &s);
  EXPECT_EQ(&s.for_run(nsf::DecoderFamily::mlp, "basis"), &s);
  const RomSection& mlp = s.for_run(nsf::DecoderFamily::mlp, "tracked");
  EXPECT_EQ(mlp.sampling.count, 200);
  EXPECT_EQ(mlp.quadrature, 1);
  EXPECT_FALSE(mlp.latent_prior);  // the model's calibration (of the tracked state) speaks
  EXPECT_EQ(mlp.dt_ratio, 1.4);
  EXPECT_EQ(mlp.fields.affine, "tracked");
  EXPECT_EQ(s.for_run(nsf::DecoderFamily::basis).sampling.count, 500);
  EXPECT_EQ(s.for_run(nsf::DecoderFamily::basis).latent_prior, 0.0);
  const RomSection& basis = s.for_run(nsf::DecoderFamily::basis, "tracked");
  EXPECT_EQ(basis.sampling.count, 300);  // the family's tracked object over the common one
  EXPECT_EQ(basis.dt_ratio, 1.4);
  EXPECT_FALSE(basis.latent_prior);
  // The section's own stress source decides where the command line names none.
  const RomSection own = parse_rom_section(
      json::parse(R"({"fields": {"stress": "tracked"}, "tracked": {"samples": 40}})"));
  EXPECT_TRUE(own.tracks_stress(nsf::DecoderFamily::basis));
  EXPECT_EQ(own.for_run(nsf::DecoderFamily::basis).sampling.count, 40);
  EXPECT_FALSE(own.tracks_stress(nsf::DecoderFamily::basis, "network"));

  expect_rejected(json::parse(R"({"tracked": 1})"), {"rom.tracked", "must be an object"});
  expect_rejected(json::parse(R"({"tracked": {"basis": {}}})"), {"rom.tracked.basis"});
  expect_rejected(json::parse(R"({"tracked": {"tracked": {}}})"), {"rom.tracked.tracked"});
  expect_rejected(json::parse(R"({"tracked": {"fields": {"stress": "basis"}}})"),
                  {"rom.tracked.fields.stress"});
  expect_rejected(json::parse(R"({"tracked": {"dt_ratio": 0}})"), {"rom.tracked", "rom.dt_ratio"});
}

// The settings of a run outside the model's training family (rom/setup/rom_setup.h): the common
// ones with the unseen object over them, and none of a family's or the tracked state's.
TEST(RomSection, TheUnseenProfileMergesOverTheCommonSettingsAlone) {
  const RomSection s = parse_rom_section(json::parse(R"({
    "samples": 200, "quadrature": 2, "latent_prior": 0.001,
    "unseen": {"samples": 100, "latent_prior": 0, "cfl": 0.85,
               "fields": {"stress": "tracked", "affine": "tracked"}},
    "basis": {"samples": 500}, "tracked": {"dt_ratio": 1.4}
  })"));
  ASSERT_TRUE(s.unseen);
  EXPECT_EQ(s.unseen->sampling.count, 100);
  EXPECT_EQ(s.unseen->quadrature, 2);
  EXPECT_EQ(s.unseen->latent_prior, 0.0);
  EXPECT_EQ(s.unseen->cfl, 0.85);
  EXPECT_FALSE(s.unseen->dt_ratio);  // not the tracked object's
  EXPECT_EQ(s.unseen->fields.stress, "tracked");
  EXPECT_FALSE(s.unseen->unseen || s.unseen->basis || s.unseen->tracked);
  // The family's and tracked objects neither hold nor see it.
  EXPECT_EQ(s.for_run(nsf::DecoderFamily::basis).sampling.count, 500);
  EXPECT_FALSE(s.for_run(nsf::DecoderFamily::basis).unseen);
  EXPECT_FALSE(parse_rom_section(json::parse(R"({"samples": 9})")).unseen);

  expect_rejected(json::parse(R"({"unseen": 1})"), {"rom.unseen", "must be an object"});
  expect_rejected(json::parse(R"({"unseen": {"basis": {}}})"), {"rom.unseen.basis"});
  expect_rejected(json::parse(R"({"unseen": {"tracked": {}}})"), {"rom.unseen.tracked"});
  expect_rejected(json::parse(R"({"basis": {"unseen": {}}})"), {"rom.basis.unseen"});
  expect_rejected(json::parse(R"({"unseen": {"samples": -1}})"), {"rom.unseen"});
  EXPECT_EQ(parse_rom_section(json::parse(R"({"profile": "unseen"})")).profile, "unseen");
  EXPECT_EQ(parse_rom_section(json::parse(R"({"samples": 9})")).profile, "");
  expect_rejected(json::parse(R"({"profile": "sideways"})"), {"rom.profile", "\"family\""});
}

}  // namespace
}  // namespace nsf
