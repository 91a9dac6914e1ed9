// A bounded mutation fuzz of the model loader (#28 item 21): a small basis model and a small MLP
// model, mutated byte by byte (half of them with the checksum made to match again, as someone
// tampering on purpose would) or entry by entry (hostile sizes, NaN, wrong tensor shapes, odd
// strings under a valid checksum), then loaded and used as `nsf rom` and `nsf eval` do: checked
// against the scene, a frame encoded, the fields evaluated. Every case must work or stop with
// nsf::Error, within a time limit. Replay: NSF_FUZZ_SEED=<seed> [NSF_FUZZ_ONLY=<case>]
// nsf_nn_tests --gtest_filter='FuzzModel.*'
#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "core/error.h"
#include "error_matchers.h"
#include "fuzz_harness.h"
#include "nn/checked_archive.h"
#include "nn/field_checks.h"
#include "nn/gauss_newton.h"
#include "nn/latent_inversion.h"
#include "nn/model/access.h"
#include "nn/model/neural_model.h"
#include "nn/network_samples.h"
#include "nn/neural_fields.h"
#include "rom/inversion/latent_prior.h"
#include "small_model.h"

#include <torch/torch.h>

namespace {

namespace fs = std::filesystem;
using namespace nsf::testing::fuzz;

constexpr int kParticles = nsf::testing::kSmallModelParticles;
using nsf::testing::small_model;
std::vector<nsf::Vec3> rest_positions() {
  return nsf::testing::small_model_rest_positions();
}

// The top-level entries of a model file by kind, for the entry-level mutations.
const std::vector<std::string> kIntegers = {
    "format_version",  "latent_dim",        "depth",
    "width_g",         "width_h",           "width_l",
    "encoder_hidden",  "encoder_channels",  "encoder_max_length",
    "scene_particles", "coefficient_width", "coefficient_depth",
    "modes_u",         "modes_tau",         "modes_C"};
const std::vector<std::string> kDoubles = {"mu_min", "mu_max", "train_seconds", "latent_prior"};
const std::vector<std::string> kStrings = {"format", "nsf_version", "scene_name", "scene_x_hash",
                                           "decoder"};
const std::vector<std::string> kBools = {"stress_uses_mu", "has_mu", "displacement"};
const std::vector<std::string> kTensors = {
    "norm_X_mean",   "norm_X_std",   "norm_x_mean",   "norm_z_mean",   "norm_z_std",
    "norm_mu_mean",  "norm_mu_std",  "norm_tau_mean", "norm_tau_std",  "norm_C_mean",
    "norm_C_std",    "norm_u_mean",  "norm_u_std",    "rest",          "trajectory_latents",
    "trajectory_mu", "basis_u_mean", "basis_u_modes", "basis_u_scale", "basis_tau_modes",
    "basis_C_scale"};

// Writes `m` with one entry replaced by a hostile value of its type; returns what it did.
std::string write_with_hostile_entry(const nsf::NeuralModel& m, const std::string& path,
                                     std::mt19937_64& rng) {
  torch::serialize::OutputArchive a;
  m.write(a);
  auto pick = [&](const auto& v) { return v[rng() % v.size()]; };
  std::string key, value;
  switch (rng() % 5) {
    case 0: {
      key = pick(kIntegers);
      const int64_t v = pick(std::vector<int64_t>{-1, 0, 1, 1000000, 2147483647, int64_t(1) << 40,
                                                  std::numeric_limits<int64_t>::min()});
      a.write(key, c10::IValue(v));
      value = std::to_string(v);
      break;
    }
    case 1: {
      key = pick(kDoubles);
      const double v = pick(std::vector<double>{std::nan(""), INFINITY, -INFINITY, -1e308, 0.0});
      a.write(key, c10::IValue(v));
      value = std::to_string(v);
      break;
    }
    case 2: {
      key = pick(kStrings);
      value = pick(std::vector<std::string>{"", "zz", "ffffffffffffffffffffffff", "-1",
                                            std::string(5000, 'x'), "mlp", "basis",
                                            "x'; system \"touch PWNED\"; #", "nsf-model"});
      a.write(key, c10::IValue(value));
      break;
    }
    case 3: {
      key = pick(kBools);
      a.write(key, c10::IValue(rng() % 2 == 0));
      value = "flipped or kept";
      break;
    }
    default: {
      key = pick(kTensors);
      const std::vector<torch::Tensor> t = {torch::zeros({0}),
                                            torch::zeros({7}),
                                            torch::zeros({kParticles, 5}),
                                            torch::full({kParticles, 3}, std::nanf("")),
                                            torch::full({2}, std::nanf("")),
                                            torch::zeros({3}, torch::kInt64),
                                            torch::zeros({}),
                                            torch::zeros({2, 2, 2, 2})};
      const size_t k = rng() % t.size();
      a.write(key, t[k], /*is_buffer=*/true);
      value = "tensor " + std::to_string(k);
      break;
    }
  }
  nsf::save_checked_archive(a, path, "model file");
  return "entry '" + key + "' = " + value;
}

// A checksum that matches the bytes again, as save_checked_archive computes it (the last 8
// characters, over every byte before the comment-length field), when the file still ends in one.
void refresh_checksum(std::string& b) {
  const size_t comment = 18, record = 22;
  if (b.size() < comment + record || b.compare(b.size() - comment, 10, "nsf-crc32 ") != 0) return;
  const uLong crc = crc32(crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(b.data()),
                          uInt(b.size() - comment - 2));
  char hex[9];
  std::snprintf(hex, sizeof hex, "%08lx", crc & 0xffffffffUL);
  b.replace(b.size() - 8, 8, hex);
}

// The zip comment that holds the checksum removed (its length set to 0), when the file still
// ends in one: a file as any zip tool rewriting it would leave it.
void strip_checksum(std::string& b) {
  const size_t comment = 18;
  if (b.size() < comment + 22 || b.compare(b.size() - comment, 10, "nsf-crc32 ") != 0) return;
  b.resize(b.size() - comment);
  b[b.size() - 2] = b[b.size() - 1] = 0;
}

// 4 to 64 bytes of 0xFF (NaN in float32) somewhere in the file: most of a model's bytes are
// tensor data, so this mostly puts NaN into weights, as the issue's damaged encoder had.
std::string nan_bytes(std::string b, ByteMutator& m, std::string& what) {
  const size_t at = m.below(b.size()), len = std::min(b.size() - at, 4 + m.below(61));
  std::fill(b.begin() + long(at), b.begin() + long(at + len), '\xff');
  what = std::to_string(len) + " bytes of 0xFF at " + std::to_string(at);
  return b;
}

std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// What `nsf rom` and `nsf eval` do with a model: load it, check it against the scene, encode a
// frame, evaluate the fields at the particles and refuse them if they are not finite (eval's row
// rule), then invert the deformation at the samples under the latent prior, as the ROM's stepper
// does first (a NaN weight crashed there, in LatentPrior::closest).
void load_and_use(const std::string& path) {
  torch::set_num_threads(1);
  nsf::NeuralFields f = nsf::NeuralFields::load(path);
  const std::vector<nsf::Vec3> X = rest_positions();
  f.check_scene("fuzz", X, "the scene");
  const nsf::Latent z = f.encode(X);
  const nsf::NeuralFields::Points points = f.prepare(X);
  std::vector<nsf::Vec3> x;
  std::vector<nsf::Mat3> tau, C;
  f.deform(points, z, x);
  f.stress(points, z, 1.5, tau);
  const nsf::Latent zdot = nsf::Latent::Zero(z.size());  // C's map reads the latent velocity
  f.affine(points, z, C, 1.5, &zdot);
  nsf::require_finite_fields(z, x, tau, C, "model " + path, "the rest frame", 0);
  nsf::NeuralModel& m = nsf::torch_model(f);
  if (!m.trajectory_latents.defined()) return;
  const torch::Tensor t = m.trajectory_latents.to(torch::kFloat64).contiguous();
  const int64_t runs = t.size(0), frames = t.size(1), r = t.size(2);
  std::vector<std::vector<Eigen::VectorXd>> latents(static_cast<size_t>(runs));
  for (int64_t j = 0; j < runs; ++j)
    for (int64_t i = 0; i < frames; ++i)
      latents[size_t(j)].push_back(
          Eigen::Map<const Eigen::VectorXd>(t.data_ptr<double>() + (j * frames + i) * r, r));
  const torch::Tensor sd = m.norm_z.std.to(torch::kFloat64).contiguous();
  const nsf::LatentPrior prior(latents,
                               Eigen::Map<const Eigen::VectorXd>(sd.data_ptr<double>(), r));
  std::vector<uint32_t> ids;
  for (uint32_t p = 0; p < uint32_t(kParticles); p += 4) ids.push_back(p);
  std::vector<nsf::Vec3> target;
  for (uint32_t p : ids) target.push_back(X[p] + nsf::Vec3(0.001, 0, 0));
  nsf::GaussNewtonOptions o;
  o.penalty = &prior;
  o.penalty_length = 0.001;
  nsf::invert_deformation(*nsf::sample_deformation(m, X, ids), target, z, o);
}

// The checksum a results row records (docs/RESULTS.md, `model_crc32`) is the one the file
// carries, read without loading it; a file without one, or no file, gives "".
TEST(FuzzModel, TheStoredChecksumIsReadFromTheFilesEnd) {
  const fs::path dir =
      fs::path(::testing::TempDir()) / ("nsf_model_checksum_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string path = (dir / "a.nsf").string();
  torch::serialize::OutputArchive a;
  a.write("x", torch::ones({3}), /*is_buffer=*/true);
  nsf::save_checked_archive(a, path, "model file");
  const std::string bytes = bytes_of(path);
  const std::string crc = nsf::stored_checksum(path);
  ASSERT_EQ(crc.size(), 8u);
  EXPECT_EQ(crc, bytes.substr(bytes.size() - 8));
  std::string changed = bytes;
  changed[0] ^= 1;
  refresh_checksum(changed);
  std::ofstream((dir / "b.nsf").string(), std::ios::binary) << changed;
  EXPECT_NE(nsf::stored_checksum((dir / "b.nsf").string()), crc);
  std::ofstream((dir / "plain.nsf").string()) << "not an archive";
  EXPECT_EQ(nsf::stored_checksum((dir / "plain.nsf").string()), "");
  EXPECT_EQ(nsf::stored_checksum((dir / "missing.nsf").string()), "");
  fs::remove_all(dir);
}

// A model file whose checksum matches but whose entries were not written by nsf (a hostile or
// damaged file): each is refused with a message naming the entry, before anything is allocated
// or evaluated. Before, a non-hex scene hash escaped as "internal error: stoull", a tensor of
// the wrong shape or a basis model without rest positions loaded and failed mid-evaluation with
// a torch message, and a width of 10^6 asked for terabytes.
TEST(FuzzModel, EntriesNsfNeverWritesAreNamedErrorsUnderAValidChecksum) {
  const fs::path dir =
      fs::path(::testing::TempDir()) / ("nsf_model_entries_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string path = (dir / "m.nsf").string();
  auto refused = [&](const nsf::NeuralModel& m, const std::string& key, const c10::IValue* value,
                     const torch::Tensor* tensor) {
    torch::serialize::OutputArchive a;
    m.write(a);
    if (value) a.write(key, *value);
    if (tensor) a.write(key, *tensor, /*is_buffer=*/true);
    nsf::save_checked_archive(a, path, "model file");
    const Result r = run_bounded([&] { load_and_use(path); }, 60);
    EXPECT_EQ(r.outcome, Outcome::NamedError)
        << key << ": " << outcome_name(r.outcome) << ": " << r.detail;
    return r.detail;
  };
  const nsf::NeuralModel basis = small_model("basis"), mlp = small_model("mlp");
  const c10::IValue bad_hash(std::string("zz")), huge(int64_t(1000000)), wide(int64_t(1) << 40);
  nsf::testing::expect_contains(refused(basis, "scene_x_hash", &bad_hash, nullptr),
                                "'scene_x_hash'");
  nsf::testing::expect_contains(refused(mlp, "width_h", &huge, nullptr), "more than the file's");
  nsf::testing::expect_contains(refused(basis, "coefficient_width", &wide, nullptr),
                                "'coefficient_width'");
  const torch::Tensor wrong = torch::zeros({kParticles, 5}), nan = torch::full({2}, std::nanf(""));
  nsf::testing::expect_contains(refused(basis, "rest", nullptr, &wrong), "'rest'");
  const torch::Tensor poly = torch::zeros({3, 3}, torch::kFloat64);  // d + 1 = 6 rows expected
  nsf::testing::expect_contains(refused(basis, "map_C_poly", nullptr, &poly),
                                "damaged coefficient map of C");
  nsf::testing::expect_contains(refused(mlp, "norm_z_std", nullptr, &nan), "'norm_z_std'");
  // A calibrated latent prior no calibration gives (negative), or one without its table.
  const c10::IValue negative(-0.001), alone(0.001);
  nsf::testing::expect_contains(refused(basis, "latent_prior", &negative, nullptr),
                                "'latent_prior'");
  nsf::testing::expect_contains(refused(basis, "latent_prior", &alone, nullptr), "'latent_prior'");
  // A basis model not in displacement form would have no rest positions to add to its bases.
  const c10::IValue no(false);
  nsf::testing::expect_contains(refused(basis, "displacement", &no, nullptr), "'displacement'");
  // Weights of another width than the configuration's: g was saved 8 wide, the file says 16.
  const c10::IValue sixteen(int64_t(16));
  nsf::testing::expect_contains(refused(mlp, "width_g", &sixteen, nullptr), "network 'g'");
  fs::remove_all(dir);
}

// #54 item 7: a network weight of NaN (the issue filled the encoder's fc2 with 0xFF and made the
// checksum match) crashed the ROM's first inversion in LatentPrior::closest. It is refused on
// load, naming the network; and the prior and the inversion refuse a NaN latent by name.
TEST(FuzzModel, ANaNWeightIsRefusedOnLoadNamingItsNetwork) {
  const fs::path dir =
      fs::path(::testing::TempDir()) / ("nsf_model_nan_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  torch::manual_seed(7);
  for (const std::string decoder : {"basis", "mlp"}) {
    nsf::NeuralModel m = small_model(decoder);
    {
      torch::NoGradGuard no_grad;
      auto params = m.encoder->named_parameters();
      torch::Tensor w = params[params.size() - 1].value();  // the encoder's last layer
      w.fill_(std::nanf(""));
    }
    const std::string path = (dir / (decoder + ".nsf")).string();
    m.save(path);
    const Result r = run_bounded([&] { load_and_use(path); }, 60);
    EXPECT_EQ(r.outcome, Outcome::NamedError) << decoder << ": " << r.detail;
    nsf::testing::expect_contains(r.detail, "network 'encoder'");
    nsf::testing::expect_contains(r.detail, "NaN or infinite weight");
  }
  const std::vector<std::vector<Eigen::VectorXd>> runs = {
      {Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0)},
      {Eigen::Vector2d(0, 1), Eigen::Vector2d(1, 1)}};
  const nsf::LatentPrior prior(runs, Eigen::Vector2d(1, 1));
  const Eigen::Vector2d nan(std::nan(""), 0);
  const Result near = run_bounded([&] { prior.nearest(nan); }, 30);
  EXPECT_EQ(near.outcome, Outcome::NamedError) << near.detail;
  nsf::testing::expect_contains(near.detail, "latent prior");
  const nsf::NeuralModel basis = small_model("basis");
  const std::string path = (dir / "ok.nsf").string();
  basis.save(path);
  const Result inv = run_bounded(
      [&] {
        nsf::NeuralFields f = nsf::NeuralFields::load(path);
        const std::vector<uint32_t> ids = {0, 1, 2, 3};
        std::vector<nsf::Vec3> target(4, nsf::Vec3::Zero());
        nsf::invert_deformation(
            *nsf::sample_deformation(nsf::torch_model(f), rest_positions(), ids), target, nan,
            nsf::GaussNewtonOptions{});
      },
      30);
  EXPECT_EQ(inv.outcome, Outcome::NamedError) << inv.detail;
  nsf::testing::expect_contains(inv.detail, "starting latent");
  fs::remove_all(dir);
}

// #54 item 8: a model nsf wrote with a checksum that has none now (one byte appended, the last
// byte cut, the zip comment removed) is damaged, not "written before nsf stored one" (the first
// two are caught by the zip's own end record, the third by the format version or its entry). Both
// families: the basis model's format version postdates checksums, and the MLP model's (3) says so
// by its `checksummed` entry. A file of version 3 written without one still loads, with a note.
TEST(FuzzModel, AFileNsfWroteWithAChecksumIsRefusedWithoutOne) {
  const fs::path dir =
      fs::path(::testing::TempDir()) / ("nsf_model_strip_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  torch::manual_seed(7);
  for (const std::string decoder : {"basis", "mlp"}) {
    const std::string path = (dir / (decoder + ".nsf")).string();
    small_model(decoder).save(path);
    const std::string original = bytes_of(path);
    std::string stripped = original;
    strip_checksum(stripped);
    ASSERT_NE(stripped, original);
    const std::vector<std::pair<std::string, std::string>> damaged = {
        {"one byte appended", original + "x"},
        {"last byte cut", original.substr(0, original.size() - 1)},
        {"zip comment removed", stripped}};
    for (const auto& [what, bytes] : damaged) {
      std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
      const Result r = run_bounded([&] { load_and_use(path); }, 60);
      EXPECT_EQ(r.outcome, Outcome::NamedError) << decoder << ", " << what << ": " << r.detail;
      if (r.outcome == Outcome::NamedError) {
        EXPECT_NE(r.detail.find(what == "zip comment removed" ? "has none now" : "is damaged"),
                  std::string::npos)
            << what << ": " << r.detail;
      }
    }
  }
  torch::serialize::OutputArchive a;  // as nsf wrote an MLP model before it stored checksums
  small_model("mlp").write(a);
  a.write("checksummed", c10::IValue(false));
  const std::string old_path = (dir / "old.nsf").string();
  nsf::save_checked_archive(a, old_path, "model file");
  std::string old = bytes_of(old_path);
  strip_checksum(old);
  std::ofstream(old_path, std::ios::binary | std::ios::trunc) << old;
  const Result r = run_bounded([&] { load_and_use(old_path); }, 60);
  EXPECT_EQ(r.outcome, Outcome::Accepted) << r.detail;
  fs::remove_all(dir);
}

// Torch's reader does not check the zip's own CRC-32s, and its TorchScript parser crashed on a
// class source with one bit flipped under a matching outer checksum (a fuzz case). Each entry is
// checked against its CRC-32 before torch reads it.
TEST(FuzzModel, AnEntryThatDoesNotMatchItsZipCrcIsRefusedBeforeTorchReadsIt) {
  const fs::path dir =
      fs::path(::testing::TempDir()) / ("nsf_model_entry_crc_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string path = (dir / "m.nsf").string();
  small_model("mlp").save(path);
  std::string bytes = bytes_of(path);
  const size_t name = bytes.find("archive/data.pkl");
  ASSERT_NE(name, std::string::npos);
  const size_t pickle = bytes.find('\x80', name);  // the pickle's protocol opcode
  ASSERT_NE(pickle, std::string::npos);
  bytes[pickle + 5] = static_cast<char>(bytes[pickle + 5] ^ 4);
  refresh_checksum(bytes);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  const Result r = run_bounded([&] { load_and_use(path); }, 60);
  EXPECT_EQ(r.outcome, Outcome::NamedError) << r.detail;
  nsf::testing::expect_contains(r.detail, "'archive/data.pkl' does not match its CRC-32");
  fs::remove_all(dir);
}

TEST(FuzzModel, MutatedModelFilesLoadOrAreRefusedWithANamedError) {
  const uint64_t seed = nsf::testing::fuzz::seed(20261126);
  const int cases = case_count(200);
  const char* only = std::getenv("NSF_FUZZ_ONLY");
  std::cout << "fuzz seed " << seed << ", " << cases << " cases (NSF_FUZZ_SEED, NSF_FUZZ_CASES)\n";
  const fs::path dir =
      fs::path(::testing::TempDir()) / ("nsf_fuzz_model_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  torch::manual_seed(7);
  const nsf::NeuralModel models[2] = {small_model("basis"), small_model("mlp")};
  std::string originals[2];
  for (int k = 0; k < 2; ++k) {
    const std::string path = (dir / ("base_" + std::to_string(k) + ".nsf")).string();
    models[k].save(path);
    ASSERT_EQ(run_bounded([&] { load_and_use(path); }, 60).outcome, Outcome::Accepted)
        << nsf::family_name(models[k].config.decoder) << " model does not load unchanged";
    originals[k] = bytes_of(path);
  }
  Tally tally;
  for (int i = 0; i < cases; ++i) {
    if (only && std::atoi(only) != i) continue;
    std::mt19937_64 rng(seed ^ (0x9e3779b97f4a7c15ull * uint64_t(i + 1)));
    const int k = i % 2;
    const std::string path = (dir / ("case_" + std::to_string(i) + ".nsf")).string();
    std::string what = std::string(nsf::family_name(models[k].config.decoder)) + " model: ";
    if (rng() % 2 == 0) {
      what += write_with_hostile_entry(models[k], path, rng);
    } else {
      ByteMutator b(rng);
      std::string detail;
      std::string bytes =
          rng() % 4 == 0 ? nan_bytes(originals[k], b, detail) : b.mutate(originals[k], detail);
      what += detail;
      if (rng() % 3 == 0) {
        bytes = b.mutate(bytes, detail);
        what += "; " + detail;
      }
      switch (rng() % 3) {
        case 0:
          refresh_checksum(bytes);
          what += ", checksum made to match";
          break;
        case 1:
          strip_checksum(bytes);
          what += ", checksum stripped";
          break;
        default:
          break;
      }
      std::ofstream(path, std::ios::binary) << bytes;
    }
    const Result r = run_bounded([&] { load_and_use(path); }, 30);
    const size_t before = tally.failures.size();
    tally.add(r, "case " + std::to_string(i) + " (" + what + ", file " + path + ")");
    if (tally.failures.size() == before) fs::remove(path);
  }
  tally.report(seed, dir.string());
}

}  // namespace
