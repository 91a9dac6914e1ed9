// GCC 12 reports false -Wmaybe-uninitialized warnings from inside Eigen's AVX-512 kernels for
// dynamic-size products (in the intrinsics headers, not in this code).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

// The per-point basis decoders (nn/train/basis_fit.h, nn/basis_decoders.h, `nsf train --decoder
// basis`): the snapshot SVD, the coefficient networks' Jacobians, training, the model file, and
// fields at points that are not particles (nn/point_interpolation.h).
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "basis_model_fixture.h"
#include "core/crc32.h"
#include "core/error.h"
#include "error_matchers.h"
#include "nn/basis_decoders.h"
#include "nn/checked_bytes.h"
#include "nn/dataset.h"
#include "nn/evaluate.h"
#include "nn/latent_inversion.h"
#include "nn/model/access.h"
#include "nn/model/neural_model.h"
#include "nn/model_record.h"
#include "nn/neural_fields.h"
#include "nn/point_interpolation.h"
#include "nn/torch_settings.h"
#include "nn/train/basis_fit.h"
#include "nn/train/trainer.h"
#include "nn/zip_entries.h"
#include "nn_fixtures.h"

#include <torch/torch.h>

namespace fs = std::filesystem;
using nsf::Latent;
using nsf::NeuralFields;
using nsf::Vec3;

using nsf::test::bit_identical;
using nsf::testing::basis::basis_options;
using nsf::testing::basis::BasisModel;
using nsf::testing::basis::kParticles;
using nsf::testing::basis::outputs;

namespace {

// Rows: a rank-3 signal plus small noise, 40 frames of 50 points × dim values.
Eigen::MatrixXf low_rank_frames(int frames, int columns, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> n(0.0f, 1.0f);
  Eigen::MatrixXf A(frames, columns);
  Eigen::MatrixXf U(frames, 3), V(3, columns);
  for (int i = 0; i < U.size(); ++i) U.data()[i] = n(rng);
  for (int i = 0; i < V.size(); ++i) V.data()[i] = n(rng);
  A = U * V;
  for (int i = 0; i < A.size(); ++i) A.data()[i] += 0.01f * n(rng) + 0.5f;
  return A;
}

}  // namespace

// The basis reproduces each training frame to its projection error: the modes are orthonormal in
// the weighted norm, the coefficients are the frames' projections, and what the K modes leave is
// exactly the variance they do not hold.
TEST(BasisFit, ReproducesTrainingFramesToTheirProjectionError) {
  const int frames = 40, columns = 300;  // 50 points × 6 values (τ's layout)
  const Eigen::MatrixXf A = low_rank_frames(frames, columns, 3);
  const std::vector<double> w = {1, 1, 1, std::sqrt(2.0), std::sqrt(2.0), std::sqrt(2.0)};
  const auto fill = [&](size_t i, float* row) {
    for (int c = 0; c < columns; ++c) row[c] = A(Eigen::Index(i), c);
  };
  for (int K : {2, 3, 8}) {
    const nsf::SnapshotBasis b = nsf::fit_snapshot_basis(frames, columns, fill, w, K);
    ASSERT_EQ(b.modes.cols(), K);
    // Orthonormal in the weighted norm.
    Eigen::MatrixXd Vw = b.modes.cast<double>();
    for (int c = 0; c < columns; ++c) Vw.row(c) *= w[size_t(c % 6)];
    EXPECT_LT((Vw.transpose() * Vw - Eigen::MatrixXd::Identity(K, K)).norm(), 1e-4) << K;
    double residual = 0;
    for (int i = 0; i < frames; ++i) {
      const Eigen::VectorXd rebuilt =
          (b.mean + b.modes * b.coeffs.row(i).transpose()).cast<double>();
      for (int c = 0; c < columns; ++c) {
        const double d = w[size_t(c % 6)] * (rebuilt[c] - A(i, c));
        residual += d * d;
      }
    }
    EXPECT_NEAR(residual / b.total_energy, b.residual_share(), 1e-4) << K;
    if (K >= 3) {
      EXPECT_LT(b.residual_share(), 1e-3) << "rank 3 plus noise, K = " << K;
    } else {
      EXPECT_GT(b.residual_share(), 1e-2);
    }
  }
  EXPECT_THROW(nsf::fit_snapshot_basis(1, columns, fill, w, 4), nsf::Error);
}

// A cap on the frames × columns matrix (a paper-size scene's τ and C) takes the columns in
// slices of whole Gram blocks, each read twice: the same Gram matrix, mean and coefficients bit
// for bit, the same modes to float round-off, in a quarter of the memory here.
TEST(BasisFit, ColumnSlicesUnderAMemoryCapGiveTheSameBasis) {
  const int frames = 20, columns = 3 * 8192 + 300;  // four slices of one 8192-column block
  const Eigen::MatrixXf A = low_rank_frames(frames, columns, 5);
  const std::vector<double> w = {1, 1, 1, std::sqrt(2.0), std::sqrt(2.0), std::sqrt(2.0)};
  size_t calls = 0;
  const auto fill = [&](size_t i, float* row) {
    ++calls;
    for (int c = 0; c < columns; ++c) row[c] = A(Eigen::Index(i), c);
  };
  const nsf::SnapshotBasis whole = nsf::fit_snapshot_basis(frames, columns, fill, w, 4);
  EXPECT_EQ(calls, size_t(frames));
  calls = 0;
  const nsf::SnapshotBasis sliced =
      nsf::fit_snapshot_basis(frames, columns, fill, w, 4, frames * sizeof(float) * 8192);
  EXPECT_EQ(calls, size_t(2 * 4 * frames));  // two passes of four slices
  EXPECT_TRUE(sliced.mean == whole.mean);
  EXPECT_TRUE(sliced.sigma == whole.sigma);
  EXPECT_TRUE(sliced.coeffs == whole.coeffs);
  EXPECT_EQ(sliced.total_energy, whole.total_energy);
  ASSERT_EQ(sliced.modes.rows(), whole.modes.rows());
  // Float round-off, not a wrong slice (that would be of the order of the modes themselves): the
  // modes are float GEMMs over the slices, which OpenBLAS sums in another order on each CPU
  // (8e-6 of the largest entry on an AMD EPYC, under 1e-6 on the Intel machines before).
  EXPECT_LT((sliced.modes - whole.modes).cwiseAbs().maxCoeff(),
            1e-4f * whole.modes.cwiseAbs().maxCoeff());
}

// ∂c/∂ẑ of a coefficient network, and ∂g/∂ẑ = B ∂c/∂ẑ at the samples, against central differences.
TEST(BasisDecoders, JacobiansMatchFiniteDifferences) {
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, 0.7);
  nsf::CoefficientNet net;
  const int sizes[] = {3, 16, 16, 5};
  for (int i = 0; i < 3; ++i) {
    net.W.push_back(Eigen::MatrixXd::NullaryExpr(sizes[i + 1], sizes[i], [&] { return n(rng); }));
    net.b.push_back(Eigen::VectorXd::NullaryExpr(sizes[i + 1], [&] { return n(rng); }));
  }
  net.in_shift.resize(3), net.in_scale.resize(3);
  net.in_shift << 0.1, -0.2, 0.3;
  net.in_scale << 2.0, 0.5, 1.5;
  net.out_scale = Eigen::VectorXd::LinSpaced(5, 0.5, 3.0);
  Eigen::VectorXd z(3);
  z << 0.3, -0.4, 0.9;
  Eigen::MatrixXd J;
  net(z, &J);
  const double h = 1e-6;
  for (int k = 0; k < 3; ++k) {
    const Eigen::VectorXd e = h * Eigen::VectorXd::Unit(3, k);
    const Eigen::VectorXd fd = (net(z + e) - net(z - e)) / (2 * h);
    EXPECT_LT((J.col(k) - fd).norm(), 1e-6 * (1 + fd.norm())) << "column " << k;
  }

  nsf::PointBasis u;
  u.dim = 3, u.K = 5, u.points = 7;
  std::uniform_real_distribution<float> uf(-1.0f, 1.0f);
  for (size_t i = 0; i < 7 * 3; ++i) u.mean.push_back(uf(rng));
  for (size_t i = 0; i < 7 * 3 * 5; ++i) u.modes.push_back(uf(rng));
  u.net = net;
  std::vector<Vec3> rest(7);
  for (Vec3& X : rest) X = Vec3(uf(rng), uf(rng), uf(rng));
  nsf::BasisSamples samples(u, rest);
  Eigen::MatrixXd Jg;
  std::vector<Vec3> g, gp, gm;
  samples.jacobian(z, Jg, g);
  ASSERT_EQ(Jg.rows(), 21);
  const double step = 1e-3;  // float bases: a larger step, a looser tolerance
  for (int k = 0; k < 3; ++k) {
    samples.evaluate(z + step * Eigen::VectorXd::Unit(3, k), gp);
    samples.evaluate(z - step * Eigen::VectorXd::Unit(3, k), gm);
    for (size_t p = 0; p < 7; ++p)
      for (int c = 0; c < 3; ++c) {
        const double fd = (gp[p][c] - gm[p][c]) / (2 * step);
        EXPECT_NEAR(Jg(3 * Eigen::Index(p) + c, k), fd, 2e-3 * (1 + std::abs(fd)));
      }
  }
}

// MLS reproduces a field affine in X exactly (away from particles too); a point on a particle
// takes that particle's value alone; nearest takes the nearest particle's.
TEST(PointInterpolation, MlsIsExactForAffineFieldsAndPointsOnParticlesAreExact) {
  const nsf::Particles P = nsf::test::synthetic_particles(400, 9);
  auto field = [](const Vec3& X) { return 0.3 + 2.0 * X.x() - X.y() + 0.5 * X.z(); };
  std::vector<Vec3> points = {Vec3(0.5, 0.5, 0.5), Vec3(0.31, 0.62, 0.44), P.X[17]};
  const nsf::PointInterpolation mls = nsf::interpolate_points(P.X, points, "mls", 16);
  ASSERT_EQ(mls.size(), 3u);
  for (size_t i = 0; i < points.size(); ++i) {
    double v = 0, wsum = 0;
    for (uint32_t e = mls.start[i]; e < mls.start[i + 1]; ++e)
      v += mls.weight[e] * field(P.X[mls.particle[e]]), wsum += mls.weight[e];
    EXPECT_NEAR(v, field(points[i]), 1e-5) << i;
    EXPECT_NEAR(wsum, 1.0, 1e-5) << i;
  }
  EXPECT_EQ(mls.start[3] - mls.start[2], 1u);
  EXPECT_EQ(mls.particle[mls.start[2]], 17u);
  const nsf::PointInterpolation nearest = nsf::interpolate_points(P.X, points, "nearest");
  for (size_t i = 0; i < points.size(); ++i) {
    const uint32_t p = nearest.particle[nearest.start[i]];
    for (size_t q = 0; q < P.size(); ++q)
      EXPECT_LE((P.X[p] - points[i]).norm(), (P.X[q] - points[i]).norm() + 1e-15);
  }
  nsf::testing::expect_contains(
      nsf::testing::error_of([&] { nsf::interpolate_points(P.X, points, "cubic"); }),
      "unknown scheme 'cubic'");
}

// The synthetic fields have rank 2 in (a, b): four modes hold them, so the bases reproduce every
// frame (held-out too) to round-off, and the trained coefficients come close.
TEST_F(BasisModel, HoldsTheFieldsAndItsProjectionBoundsTheModel) {
  ASSERT_TRUE(report_.completed);
  NeuralFields nf = NeuralFields::load(model());
  EXPECT_EQ(nf.decoder(), "basis");
  ASSERT_NE(nf.bases(), nullptr);
  // Rank 2 plus the mean: the fit keeps the modes above round-off, at most the 4 asked for.
  EXPECT_GE(nf.bases()->u.K, 2);
  EXPECT_LE(nf.bases()->u.K, 4);
  EXPECT_GT(nf.train_seconds(), 0.0);
  for (const char* split : {"train", "test"}) {
    nsf::EvalOptions o;
    o.split = split;
    for (const nsf::EvalRow& r : nsf::evaluate_model(model(), data(), o)) {
      EXPECT_LT(r.projection_delta, 1e-5) << split;
      EXPECT_LT(r.projection_stress, 1e-4) << split;
      EXPECT_LT(r.projection_affine, 1e-4) << split;
      EXPECT_LE(r.projection_delta, r.delta) << split;
      EXPECT_LE(r.projection_stress, r.stress_error) << split;
      EXPECT_LT(r.delta, 0.01) << split << " " << r.run;
      EXPECT_LT(r.stress_error, 0.2) << split << " " << r.run;
      EXPECT_LT(r.affine_error, 0.2) << split << " " << r.run;
    }
  }
}

// `nsf eval --held-out-particles`: every 5th particle read from the others. The synthetic fields
// vary smoothly in X, so moving least squares reads them better than the nearest particle does,
// and a held-out particle is never read from itself.
TEST_F(BasisModel, HeldOutParticlesAreReadFromTheOthers) {
  nsf::EvalOptions o;
  o.held_out_stride = 5;
  const std::vector<nsf::EvalRow> mls = nsf::evaluate_model(model(), data(), o);
  o.interpolation = "nearest";
  const std::vector<nsf::EvalRow> nearest = nsf::evaluate_model(model(), data(), o);
  ASSERT_EQ(mls.size(), nearest.size());
  for (size_t i = 0; i < mls.size(); ++i) {
    const nsf::HeldOutErrors& h = mls[i].held_out;
    EXPECT_EQ(h.particles, size_t(kParticles / 5));
    EXPECT_NE(h.delta, h.own_delta);
    EXPECT_LT(h.delta, nearest[i].held_out.delta);
    EXPECT_LT(h.stress, nearest[i].held_out.stress);
    EXPECT_EQ(h.own_delta, nearest[i].held_out.own_delta);
  }
  o.held_out_stride = 1;
  nsf::testing::expect_contains(
      nsf::testing::error_of([&] { nsf::evaluate_model(model(), data(), o); }), "K >= 2");
}

// A model saved and loaded gives bit-identical fields, at particles and between them.
TEST_F(BasisModel, SavedAndLoadedGivesBitIdenticalFields) {
  const std::vector<double> a = outputs(model(), data());
  const std::string copy = (root_ / "copy.nsf").string();
  nsf::NeuralModel::load(model()).save(copy);
  EXPECT_TRUE(bit_identical(a, outputs(copy, data())));
  EXPECT_TRUE(bit_identical(a, outputs(model(), data())));
}

// Killed after 2,380 steps (in stage 2) and resumed: the same model to the bit.
// The torch-free runtime reads a basis model from its file's run-time record (nn/model_record.h):
// the same fields, bit for bit, as the model loaded with LibTorch, the same training latents and
// calibrations, and e(X) of the rest state stored; only what needs the networks is refused.
TEST_F(BasisModel, TorchFreeLoadGivesTheSameModel) {
  EXPECT_TRUE(bit_identical(outputs(model(), data()), outputs(model(), data(), true)));
  const NeuralFields full = NeuralFields::load(model()), bare = NeuralFields::load_basis(model());
  EXPECT_NE(full.networks(), nullptr);
  EXPECT_EQ(bare.networks(), nullptr);
  EXPECT_EQ(bare.latent_dim(), full.latent_dim());
  EXPECT_EQ(bare.particle_count(), size_t(kParticles));
  EXPECT_EQ(bare.scene_name(), full.scene_name());
  EXPECT_EQ(bare.mu_min(), full.mu_min());
  EXPECT_EQ(bare.mu_max(), full.mu_max());
  EXPECT_EQ(bare.train_seconds(), full.train_seconds());
  EXPECT_EQ(bare.training_box().to_json(), full.training_box().to_json());
  const nsf::ModelRecord &a = full.record(), &b = bare.record();
  ASSERT_FALSE(b.trajectory_latents.empty());
  ASSERT_EQ(b.trajectory_latents.size(), a.trajectory_latents.size());
  for (size_t i = 0; i < a.trajectory_latents.size(); ++i)
    for (size_t k = 0; k < a.trajectory_latents[i].size(); ++k)
      EXPECT_EQ(b.trajectory_latents[i][k], a.trajectory_latents[i][k]);
  EXPECT_EQ(b.trajectory_mu, a.trajectory_mu);
  EXPECT_EQ(b.latent_spread, a.latent_spread);
  // e(X), computed when the file was saved, is the encoder's latent of the rest state.
  const nsf::Dataset d(data());
  const Latent z_rest = full.encode(d.rest_positions());
  ASSERT_EQ(bare.rest_latent(d.rest_positions()).size(), z_rest.size());
  EXPECT_LT((bare.rest_latent(d.rest_positions()) - z_rest).norm(), 1e-6 * (1 + z_rest.norm()));
  // The record's bytes round-trip.
  const std::string bytes = nsf::encode_model_record(b);
  EXPECT_EQ(nsf::encode_model_record(nsf::decode_model_record(bytes, "x")), bytes);
  nsf::testing::expect_contains(nsf::testing::error_of([&] { bare.encode(d.rest_positions()); }),
                                "needs LibTorch");
}

// A record whose bytes changed is refused by its own CRC-32, even where the file's checksum was
// made to match again; a model without one (an MLP model) says what the runtime needs.
TEST_F(BasisModel, DamagedOrMissingRecordIsAClearError) {
  std::string bytes;
  {
    std::ifstream in(model(), std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const size_t comment = nsf::checksum_comment_length();
  std::vector<nsf::ZipEntry> entries;
  ASSERT_TRUE(nsf::zip_directory(bytes, comment, "model file", model(), entries));
  size_t at = 0;
  for (const nsf::ZipEntry& e : entries)
    if (nsf::is_model_record(bytes.data() + e.data, e.size)) at = size_t(e.data) + e.size / 2;
  ASSERT_GT(at, 0u) << "a basis model file holds a run-time record";
  bytes[at] = char(bytes[at] ^ 0x5a);
  bytes.resize(bytes.size() - comment);  // the checksum made to match the changed bytes
  bytes[bytes.size() - 2] = bytes[bytes.size() - 1] = 0;
  nsf::add_checksum(bytes, "model file", "test");
  const std::string damaged = (root_ / "damaged.nsf").string();
  std::ofstream(damaged, std::ios::binary) << bytes;
  nsf::testing::expect_contains(nsf::testing::error_of([&] { NeuralFields::load_basis(damaged); }),
                                "run-time record is damaged");

  nsf::NetConfig c;
  c.decoder = nsf::DecoderFamily::mlp;
  c.latent_dim = 2;
  c.encoder_hidden = 8;
  c.width_g = c.width_h = c.width_l = 4;
  c.depth = 1;
  const std::string mlp = (root_ / "mlp.nsf").string();
  nsf::NeuralModel net(c, nsf::SceneFingerprint{"tiny", 10, 1}, false);
  net.rest = torch::zeros({10, 3});  // the displacement form's rest positions
  net.save(mlp);
  const std::string why = nsf::testing::error_of([&] { NeuralFields::load_basis(mlp); });
  nsf::testing::expect_contains(why, "no run-time record");
  nsf::testing::expect_contains(why, "MLP model");
  EXPECT_NO_THROW(NeuralFields::load(mlp));
}

// A record with changed bytes whose CRC-32 was made to match again (a crafted file) is parsed with
// every length checked: it loads or is refused with nsf::Error, never a crash or a huge allocation.
TEST_F(BasisModel, RecordParserSurvivesCraftedBytes) {
  const std::string good = nsf::encode_model_record(NeuralFields::load_basis(model()).record());
  constexpr size_t kHeader = 24;  // magic, version, length, CRC-32
  std::mt19937 rng(7);
  int refused = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::string b = good;
    if (trial % 4 == 0) {  // cut short, the length field made to agree
      b.resize(kHeader + rng() % (good.size() - kHeader));
      const uint64_t n = b.size() - kHeader;
      std::memcpy(&b[12], &n, 8);
    } else {  // a few bytes of the first kilobyte (the sizes and counts) changed
      for (int k = 0; k < 1 + trial % 3; ++k) {
        const size_t at = kHeader + rng() % std::min<size_t>(1024, good.size() - kHeader);
        b[at] = char(rng());
      }
    }
    const uint32_t crc = nsf::crc32_of(b.data() + kHeader, b.size() - kHeader);
    std::memcpy(&b[20], &crc, 4);
    try {
      nsf::decode_model_record(b, "crafted.nsf");
    } catch (const nsf::Error& e) {
      ++refused;
      EXPECT_THAT(e.what(), ::testing::HasSubstr("crafted.nsf"));
    }
  }
  EXPECT_GT(refused, 100);
}

TEST_F(BasisModel, ResumedTrainingGivesTheSameModel) {
  const std::string m = (root_ / "resumed.nsf").string();
  nsf::TrainOptions o = basis_options();
  o.stop_after = 2380;
  EXPECT_FALSE(nsf::train_model(data(), m, o).completed);
  o.stop_after = -1;
  o.resume = true;
  EXPECT_TRUE(nsf::train_model(data(), m, o).completed);
  EXPECT_TRUE(bit_identical(outputs(m, data()), outputs(model(), data())));
}

// The model's particles are its scene's: other rest positions are a clear error, and the
// coordinate-network calls of the torch-level model refuse a basis model.
TEST_F(BasisModel, AnotherScenesParticlesAreAClearError) {
  NeuralFields nf = NeuralFields::load(model());
  const nsf::Particles other = nsf::test::synthetic_particles(kParticles, 99);
  const std::string msg =
      nsf::testing::error_of([&] { nf.check_scene("synthetic", other.X, "scene 'other'"); });
  nsf::testing::expect_contains(msg, "the model was trained for");
  nsf::testing::expect_contains(msg, "scene 'other'");
  const nsf::Particles fewer = nsf::test::synthetic_particles(kParticles - 1, 7);
  EXPECT_THROW(nf.check_scene("synthetic", fewer.X, "scene 'fewer'"), nsf::Error);
  EXPECT_THROW(nsf::torch_model(nf).deform(torch::zeros({1, 3}), torch::zeros({1, 2})), nsf::Error);
}

// --encoder modes: no encoder training; the latent of a frame is its first r coefficients of
// x − X over their spreads, the model holds the fields as the trained encoder's does, and the
// choice survives saving. It needs the bases (an MLP model has none to project on).
TEST_F(BasisModel, ModesEncoderIsTheProjectionOnTheLeadingModes) {
  nsf::TrainOptions o = basis_options();
  o.config.net.encoder = "modes";
  const std::string m = (root_ / "modes.nsf").string();
  ASSERT_TRUE(nsf::train_model(data(), m, o).completed);
  NeuralFields nf = NeuralFields::load(m);
  EXPECT_EQ(nf.encoder_kind(), "modes");
  const nsf::Dataset d(data());
  const std::vector<Vec3> x = d.read_positions(d.test()[0], 5);
  const Latent z = nf.encode(x);
  const nsf::PointBasis& u = nf.bases()->u;
  const torch::Tensor spread = nsf::torch_model(nf).basis[0].scale;
  ASSERT_EQ(z.size(), 2);
  for (int i = 0; i < 2; ++i) {
    double c = 0;
    for (size_t p = 0; p < u.points; ++p)
      for (int k = 0; k < 3; ++k)
        c += double(u.modes[(p * 3 + size_t(k)) * size_t(u.K) + size_t(i)]) *
             (x[p][k] - nf.bases()->rest[p][k] - double(u.mean[p * 3 + size_t(k)]));
    EXPECT_NEAR(z[i], c / spread[i].item<double>(), 1e-4 * (1 + std::abs(z[i]))) << i;
  }
  nsf::EvalOptions e;
  for (const nsf::EvalRow& r : nsf::evaluate_model(m, data(), e)) {
    EXPECT_LT(r.delta, 0.01) << r.run;
    EXPECT_LT(r.stress_error, 0.2) << r.run;
  }
  const std::string copy = (root_ / "modes_copy.nsf").string();
  nsf::NeuralModel::load(m).save(copy);
  EXPECT_EQ(nsf::NeuralModel::load(copy).config.encoder, "modes");
  EXPECT_TRUE(bit_identical(outputs(m, data()), outputs(copy, data())));
  nsf::TrainOptions mlp = o;
  mlp.config.net.decoder = nsf::DecoderFamily::mlp;
  nsf::testing::expect_contains(
      nsf::testing::error_of([&] { nsf::train_model(data(), (root_ / "no.nsf").string(), mlp); }),
      "the modes encoder needs the basis decoders");
}

// --stress-input velocity: τ's map reads (ẑ, μ, ż) as C's does; the model says so after saving,
// gives the same bits, and asking it for τ without ż is an internal error, not a silent zero.
TEST_F(BasisModel, StressMapThatReadsTheLatentVelocitySurvivesSaving) {
  nsf::TrainOptions o = basis_options();
  o.config.net.coefficients = {"map", "map"};
  o.config.net.stress_uses_velocity = true;
  const std::string m = (root_ / "stress_velocity.nsf").string();
  ASSERT_TRUE(nsf::train_model(data(), m, o).completed);
  NeuralFields nf = NeuralFields::load(m);
  ASSERT_NE(nf.bases(), nullptr);
  EXPECT_TRUE(nsf::torch_model(nf).config.stress_reads_velocity());
  EXPECT_TRUE(nf.bases()->stress_uses_velocity);
  const int64_t r = nf.latent_dim();
  EXPECT_EQ(nf.bases()->tau.map.inputs(), 2 * r + 1);
  nsf::EvalOptions e;
  for (const nsf::EvalRow& row : nsf::evaluate_model(m, data(), e)) {
    EXPECT_LT(row.stress_error, 0.2) << row.run;
  }
  const Latent z = Latent::Zero(r);
  std::vector<nsf::Mat3> tau;
  nsf::testing::expect_contains(
      nsf::testing::error_of([&] { nf.stress(nf.prepare(nf.bases()->rest), z, 1.0, tau); }),
      "need the latent velocity");
  const std::string copy = (root_ / "stress_velocity_copy.nsf").string();
  nsf::NeuralModel::load(m).save(copy);
  EXPECT_TRUE(nsf::NeuralModel::load(copy).config.stress_uses_velocity);
  EXPECT_TRUE(bit_identical(outputs(m, data()), outputs(copy, data())));
}

// The modes encoder's latent has the same bits at every thread count. At a paper-size scene's
// 3|P| (sand_paper: 213,588 entries) a float product splits its sum across threads, and the ROM's
// first latent, and all that follows, moved in the fourth digit of δ between -j 1 and -j 2.
TEST(ModesEncoder, LatentHasTheSameBitsAtEveryThreadCount) {
  const int64_t P = 71196, r = 6, K = 12;  // sand_paper's model
  nsf::NetConfig c;
  c.decoder = nsf::DecoderFamily::basis;
  c.encoder = "modes";
  c.latent_dim = int(r);
  c.modes = {int(K), 1, 1};
  nsf::NeuralModel m(c, nsf::SceneFingerprint{"big", P, 1}, false);
  torch::manual_seed(3);
  m.rest = torch::rand({P, 3});
  m.basis[0].mean = 1e-3 * torch::randn({P, 3});
  m.basis[0].modes = torch::randn({P, 3, K}) / std::sqrt(3.0 * double(P));
  m.basis[0].scale = torch::linspace(1, 0.1, K);
  const torch::Tensor x = m.rest.unsqueeze(0) + 0.05 * torch::randn({1, P, 3});
  const int saved = omp_get_max_threads();
  std::vector<torch::Tensor> z;
  for (int threads : {1, 2, 3}) {
    omp_set_num_threads(threads);  // as nsf rom -j sets them
    nsf::set_nn_threads(threads);
    z.push_back(m.encode(x));
  }
  omp_set_num_threads(saved);
  nsf::set_nn_threads(2);
  for (size_t t = 1; t < z.size(); ++t) {
    ASSERT_EQ(z[t].sizes(), z[0].sizes());
    EXPECT_EQ(std::memcmp(z[t].data_ptr<float>(), z[0].data_ptr<float>(), r * sizeof(float)), 0)
        << t + 1 << " threads against 1: " << (z[t] - z[0]).abs().max().item<double>();
  }
  // Still the projection: Σ_p B_p,i · (x_p − X_p − mean_p) / spread_i.
  const torch::Tensor u =
      (x - m.rest.unsqueeze(0) - m.basis[0].mean.unsqueeze(0)).reshape({1, -1}).to(torch::kFloat64);
  const torch::Tensor B = m.basis[0].modes.narrow(2, 0, r).reshape({-1, r}).to(torch::kFloat64);
  const torch::Tensor want =
      torch::matmul(u, B) / m.basis[0].scale.narrow(0, 0, r).to(torch::kFloat64);
  EXPECT_LT((z[0].to(torch::kFloat64) - want).abs().max().item<double>(),
            1e-5 * want.abs().max().item<double>());
}
