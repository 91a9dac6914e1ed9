#pragma once
// The ROM's end-to-end fixture: a sweep of scenes/examples/rom_tiny.json and two models trained on
// it, once per test process (SetUpTestSuite). Its tests run the ROM through the library
// (unit/rom/eval/test_rom_end_to_end.cpp), `nsf rom` and `nsf demo` (cli/test_rom_cli.cpp) and
// `nsf calibrate` (cli/test_rom_calibrate_cli.cpp): one suite, RomEndToEnd, trained once.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "data/sweep.h"
#include "io/run_reader.h"
#include "nn/neural_fields.h"
#include "nn/torch_settings.h"
#include "nn/train/trainer.h"
#include "rom/calibration/latent_prior_calibration.h"
#include "rom/eval/rom_evaluation.h"

namespace nsf::testing {

namespace fs = std::filesystem;

inline const std::string kTinyScene =
    (fs::path(NSF_SOURCE_DIR) / "scenes" / "examples" / "rom_tiny.json").string();

// One tiny dataset and two models (MLP fields, per-point bases) shared by the end-to-end tests.
class RomEndToEnd : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    nsf::set_nn_threads(2);
    root_ = fs::temp_directory_path() / ("nsf_rom_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    nsf::SweepOptions so;
    so.out_dir = (root_ / "data").string();
    so.jobs = 2;
    so.quiet = true;
    nsf::run_sweep(kTinyScene, so);
    nsf::TrainOptions o;
    nsf::TrainConfig& c = o.config;
    c.net.decoder = nsf::DecoderFamily::mlp;
    c.net.latent_dim = 4;
    c.net.depth = 4;
    c.net.width_g = 64;
    c.net.width_h = c.net.width_l = 64;
    c.steps = {1500, 600, 600};
    c.frames_per_batch = {4, 8, 8};
    c.particles_per_frame = {256, 256, 256};
    c.seed = 2;
    c.quiet = true;
    nsf::train_model((root_ / "data").string(), model(), o);
    // The same latent size with the per-point basis decoders (nn/basis_decoders.h).
    c.net.decoder = nsf::DecoderFamily::basis;
    c.net.modes = {16, 16, 16};
    c.net.coefficient_width = 64;
    c.net.coefficient_depth = 2;
    c.frames_per_batch = {4, 32, 32};
    nsf::train_model((root_ / "data").string(), basis_model(), o);
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }
  static std::string model() { return (root_ / "tiny.nsf").string(); }
  static std::string basis_model() { return (root_ / "tiny_basis.nsf").string(); }
  static std::string truth() { return (root_ / "data" / "test_0.h5").string(); }
  static double test_mu() { return 1.0; }  // the sweep's single test run (midpoint)

  static nsf::RomEvalOptions options() {
    nsf::RomEvalOptions o;
    o.model_path = model();
    o.scene_path = kTinyScene;
    o.mu = test_mu();
    o.truth_path = truth();
    o.full_order = false;
    o.quiet = true;
    return o;
  }
  // `nsf calibrate` on two training runs of a fresh copy `name` of the (uncalibrated) basis model.
  static nsf::CalibrationOptions calibration_options(const std::string& name) {
    nsf::CalibrationOptions co;
    co.model_path = (root_ / name).string();
    fs::copy_file(basis_model(), co.model_path, fs::copy_options::overwrite_existing);
    co.data_dir = (root_ / "data").string();
    co.scene_path = kTinyScene;
    co.runs = 2;
    co.quiet = true;
    return co;
  }
  inline static fs::path root_;
};

// The latents a ROM run wrote beside its frames (/rom/latent, frames × r).
inline std::vector<nsf::Latent> written_latents(const std::string& path) {
  size_t rows = 0, cols = 0;
  const std::vector<double> table = nsf::RunReader(path).read_table("/rom/latent", rows, cols);
  std::vector<nsf::Latent> z(rows);
  for (size_t k = 0; k < rows; ++k)
    z[k] = Eigen::Map<const nsf::Latent>(&table[k * cols], Eigen::Index(cols));
  return z;
}

}  // namespace nsf::testing
