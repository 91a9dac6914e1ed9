// The ROM's calibration as its own record (rom/calibration/rom_calibration.h): kept in the model
// file as an attachment that nn stores without reading, it comes back from a file saved now
// through both loaders (with LibTorch, and the runtime's torch-free record), and from the
// entries of files of format versions 1-8 and the numbers of a version 1 run-time record.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cstring>
#include <filesystem>
#include <string>

#include "core/crc32.h"
#include "core/error.h"
#include "error_matchers.h"
#include "nn/basis_export.h"
#include "nn/checked_archive.h"
#include "nn/model/neural_model.h"
#include "nn/model_record.h"
#include "nn/neural_fields.h"
#include "rom/calibration/rom_calibration.h"
#include "small_model.h"

namespace {

namespace fs = std::filesystem;

fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / (name + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

nsf::RomCalibrations example() {
  nsf::RomCalibrations c;
  c.decoded.latent_prior = 3e-4;
  c.decoded.dt_ratio = 1.5;
  c.decoded.table = {{"chosen", 3e-4}, {"grid", {0, 1e-4, 3e-4}}};
  c.tracked.latent_prior = 0;  // calibrated, and chose no prior
  c.tracked.table = {{"chosen", 0}};
  return c;
}

void expect_same(const nsf::RomCalibration& a, const nsf::RomCalibration& b) {
  EXPECT_EQ(a.latent_prior, b.latent_prior);
  EXPECT_EQ(a.dt_ratio, b.dt_ratio);
  EXPECT_EQ(a.table, b.table);
}

int64_t format_version(const std::string& path) {
  torch::serialize::InputArchive a;
  nsf::load_checked_archive(a, path, "model file");
  c10::IValue v;
  a.read("format_version", v);
  return v.toInt();
}

}  // namespace

TEST(CalibrationRecord, JsonRoundTripAndDamage) {
  const nsf::RomCalibrations c = example();
  const nsf::RomCalibrations back = nsf::rom_calibrations_from_json(nsf::to_json(c), "m.nsf");
  expect_same(back.decoded, c.decoded);
  expect_same(back.tracked, c.tracked);
  // Never calibrated: nothing written, everything at its default.
  EXPECT_TRUE(nsf::to_json(nsf::RomCalibrations()).empty());
  const nsf::RomCalibrations none =
      nsf::rom_calibrations_from_json(nlohmann::json::object(), "m.nsf");
  EXPECT_LT(none.decoded.latent_prior, 0);
  EXPECT_LT(none.tracked.dt_ratio, 0);
  nsf::testing::expect_contains(
      nsf::testing::error_of([] {
        nsf::rom_calibrations_from_json({{"latent_prior", -1e-3}}, "m.nsf");
      }),
      "'latent_prior'");
  nsf::testing::expect_contains(
      nsf::testing::error_of([] {
        nsf::rom_calibrations_from_json({{"tracked_calibrated_dt_ratio", 0}}, "m.nsf");
      }),
      "'tracked_calibrated_dt_ratio'");
}

// Saved now (format version 9), the record comes back whole through NeuralFields::load and, for
// a basis model, through the runtime's load_basis (its run-time record holds it too). A model
// without attachments: none, and an MLP model keeps format version 3.
TEST(CalibrationRecord, AModelSavedNowKeepsItThroughBothLoaders) {
  const fs::path dir = temp_dir("nsf_calibration_record_");
  const nsf::RomCalibrations c = example();
  for (const char* decoder : {"basis", "mlp"}) {
    SCOPED_TRACE(decoder);
    nsf::NeuralModel m = nsf::testing::small_model(decoder);
    const std::string plain = (dir / (std::string(decoder) + "_plain.nsf")).string();
    m.save(plain);
    EXPECT_EQ(nsf::NeuralFields::load(plain).attachment(nsf::kRomCalibrationAttachment), nullptr);
    EXPECT_EQ(format_version(plain), std::string(decoder) == "basis" ? 9 : 3);
    const std::string path = (dir / (std::string(decoder) + ".nsf")).string();
    m.save(path);
    nsf::NeuralFields::store_attachment(path, nsf::kRomCalibrationAttachment,
                                        nsf::to_json(c).dump());
    EXPECT_EQ(format_version(path), 9);
    EXPECT_EQ(nsf::NeuralModel::load(path).attachments.size(), 1u);
    const nsf::RomCalibrations loaded = nsf::rom_calibrations(nsf::NeuralFields::load(path));
    expect_same(loaded.decoded, c.decoded);
    expect_same(loaded.tracked, c.tracked);
    if (std::string(decoder) == "basis") {
      const nsf::RomCalibrations bare = nsf::rom_calibrations(nsf::NeuralFields::load_basis(path));
      expect_same(bare.decoded, c.decoded);
      expect_same(bare.tracked, c.tracked);
    }
  }
  fs::remove_all(dir);
}

// A file of format version 8 or older kept the calibration in entries of its own: loaded now, it
// keeps its calibration (and a damaged one is still refused, naming the entry).
TEST(CalibrationRecord, AnOldFormatFileKeepsItsCalibration) {
  const fs::path dir = temp_dir("nsf_calibration_legacy_");
  const std::string path = (dir / "old.nsf").string();
  const nsf::RomCalibrations c = example();
  for (const char* decoder : {"basis", "mlp"}) {
    SCOPED_TRACE(decoder);
    torch::serialize::OutputArchive a;
    nsf::testing::small_model(decoder).write(a);  // a basis model's bases in the archive: 4-7
    a.write("latent_prior", c10::IValue(c.decoded.latent_prior));
    a.write("latent_prior_calibration", c10::IValue(c.decoded.table.dump()));
    a.write("calibrated_dt_ratio", c10::IValue(c.decoded.dt_ratio));
    a.write("tracked_latent_prior", c10::IValue(c.tracked.latent_prior));
    a.write("tracked_latent_prior_calibration", c10::IValue(c.tracked.table.dump()));
    nsf::save_checked_archive(a, path, "model file");
    ASSERT_LE(format_version(path), 8);
    const nsf::RomCalibrations loaded = nsf::rom_calibrations(nsf::NeuralFields::load(path));
    expect_same(loaded.decoded, c.decoded);
    expect_same(loaded.tracked, c.tracked);
    // Saved again (nsf upgrade, nsf calibrate), it carries the record instead.
    nsf::NeuralModel::load(path).save(path);
    EXPECT_EQ(format_version(path), 9);
    const nsf::RomCalibrations again = nsf::rom_calibrations(nsf::NeuralFields::load(path));
    expect_same(again.decoded, c.decoded);
    expect_same(again.tracked, c.tracked);
  }
  torch::serialize::OutputArchive a;
  nsf::testing::small_model("mlp").write(a);
  a.write("tracked_calibrated_dt_ratio", c10::IValue(-2.0));
  nsf::save_checked_archive(a, path, "model file");
  nsf::testing::expect_contains(nsf::testing::error_of([&] { nsf::NeuralModel::load(path); }),
                                "'tracked_calibrated_dt_ratio'");
  fs::remove_all(dir);
}

// A run-time record of version 1 (in files of format version 8) held the calibration as four
// numbers, -1 where none: the runtime reads them as the record's entries.
TEST(CalibrationRecord, AVersion1RunTimeRecordKeepsItsNumbers) {
  nsf::ModelRecord r = nsf::model_record(nsf::testing::small_model("basis"));
  r.attachments.clear();
  std::string bytes = nsf::encode_model_record(r);
  // The payload up to where version 1 had its numbers and version 2 has its attachments' count.
  const size_t header = 8 + 4 + 8 + 4;
  const size_t at = header + 8 + r.scene.scene_name.size() + 8 + 8 + 1 + 4 + 1 + 8 + 8 + 8 +
                    r.training_box.to_json().dump().size() + 8;
  uint64_t count = 1;
  std::memcpy(&count, bytes.data() + at, 8);
  ASSERT_EQ(count, 0u);
  const double numbers[4] = {3e-4, -1, 0.002, 1.5};  // ε, step; the tracked state's ε, step
  bytes.replace(at, 8, reinterpret_cast<const char*>(numbers), sizeof numbers);
  const uint32_t version = 1, crc = nsf::crc32_of(bytes.data() + header, bytes.size() - header);
  const uint64_t size = bytes.size() - header;
  std::memcpy(&bytes[8], &version, 4);
  std::memcpy(&bytes[12], &size, 8);
  std::memcpy(&bytes[20], &crc, 4);
  const nsf::ModelRecord old = nsf::decode_model_record(bytes, "old.nsf");
  ASSERT_EQ(old.attachments.count(nsf::kRomCalibrationAttachment), 1u);
  const nsf::RomCalibrations c = nsf::rom_calibrations_from_json(
      nlohmann::json::parse(old.attachments.at(nsf::kRomCalibrationAttachment)), "old.nsf");
  EXPECT_EQ(c.decoded.latent_prior, 3e-4);
  EXPECT_LT(c.decoded.dt_ratio, 0);
  EXPECT_EQ(c.tracked.latent_prior, 0.002);
  EXPECT_EQ(c.tracked.dt_ratio, 1.5);
  EXPECT_TRUE(c.decoded.table.is_null());  // the archive's entries held the tables
}
