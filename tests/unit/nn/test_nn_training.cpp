#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "error_matchers.h"
#include "nn/config.h"
#include "nn/dataset.h"
#include "nn/evaluate.h"
#include "nn/latent_inversion.h"
#include "nn/model/neural_model.h"
#include "nn/network_samples.h"
#include "nn/neural_fields.h"
#include "nn/torch_settings.h"
#include "nn/train/trainer.h"
#include "nn_fixtures.h"
#include "nn_training_fixture.h"

namespace fs = std::filesystem;
using nsf::Latent;
using nsf::NeuralFields;
using nsf::Vec3;

using nsf::test::bit_identical;
using nsf::testing::nn_training::kParticles;
using nsf::testing::nn_training::LossCurve;
using nsf::testing::nn_training::NnTraining;
using nsf::testing::nn_training::read_losses;
using nsf::testing::nn_training::tiny_options;

namespace {

// Every field of a model at every particle of one frame, for bitwise comparisons.
std::vector<double> outputs(const std::string& model, const std::string& data) {
  NeuralFields nf = NeuralFields::load(model);
  const nsf::Dataset d(data);
  const NeuralFields::Points pts = nf.prepare(d.rest_positions());
  const Latent z = nf.encode(d.read_positions(d.test()[0], 5));
  std::vector<Vec3> x;
  std::vector<nsf::Mat3> tau, C;
  nf.deform(pts, z, x);
  nf.stress(pts, z, d.test()[0].mu, tau);
  nf.affine(pts, z, C);
  std::vector<double> out(z.data(), z.data() + z.size());
  for (const Vec3& v : x) out.insert(out.end(), v.data(), v.data() + 3);
  for (const auto& m : tau) out.insert(out.end(), m.data(), m.data() + 9);
  for (const auto& m : C) out.insert(out.end(), m.data(), m.data() + 9);
  return out;
}

double mean(const std::vector<double>& v, size_t from, size_t to) {
  double s = 0;
  for (size_t i = from; i < to; ++i) s += v[i];
  return s / double(to - from);
}

}  // namespace

TEST_F(NnTraining, EveryStageLowersItsLoss) {
  ASSERT_TRUE(report_.completed);
  ASSERT_TRUE(fs::exists(model()));
  EXPECT_FALSE(fs::exists(report_.checkpoint_path)) << "a finished run removes its checkpoint";
  const LossCurve c = read_losses(report_.loss_csv);
  const auto& steps = tiny_options().config.steps;
  for (int s = 0; s < 3; ++s) {
    ASSERT_EQ(c.loss[s].size(), size_t(steps[s])) << "stage " << s + 1;
    const double first = mean(c.loss[s], 0, 5), last = mean(c.loss[s], steps[s] - 20, steps[s]);
    // h and l cannot beat the latents stage 1 leaves them with after so few steps, hence the
    // looser factor for stages 2 and 3.
    const double factor = s == 0 ? 0.2 : 0.5;
    EXPECT_LT(last, factor * first) << "stage " << s + 1 << ": " << first << " -> " << last;
    EXPECT_GT(report_.stages[s].points_per_second, 0.0);
  }
}

TEST_F(NnTraining, EvalReportsSmallErrorsOnHeldOutRun) {
  nsf::EvalOptions o;
  const auto rows = nsf::evaluate_model(model(), data(), o);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].run, "test_0.h5");
  EXPECT_EQ(rows[0].frames, 11u);  // frames 1…11, not the initial state
  EXPECT_DOUBLE_EQ(rows[0].mu, 1.25);
  EXPECT_LT(rows[0].delta, 0.1);  // positions around 0.5, displacements up to 0.2
  // After the fixture's few hundred steps h and l are still coarse (19 % and 16 % when these
  // bounds were set); a decoder that learned nothing scores about 100 %.
  EXPECT_LT(rows[0].stress_error, 0.3);
  EXPECT_LT(rows[0].affine_error, 0.3);
  // The synthetic τ and C are polynomials of degree ≤ 2 in X: the smooth fit leaves nothing.
  EXPECT_LT(rows[0].stress_poly_fit, 1e-6);
  EXPECT_LT(rows[0].affine_poly_fit, 1e-6);
  EXPECT_TRUE(std::isfinite(rows[0].force_error));
  EXPECT_GT(rows[0].force_error, 0.0);
  // Latents refined by Gauss–Newton on positions (as the ROM finds them) fit at least as well.
  nsf::EvalOptions refined = o;
  refined.refine_iterations = 5;
  const auto r = nsf::evaluate_model(model(), data(), refined);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_LE(r[0].delta, rows[0].delta * (1 + 1e-3));
  o.split = "all";
  o.frame_stride = 5;
  o.max_particles = 50;
  const auto all = nsf::evaluate_model(model(), data(), o);
  ASSERT_EQ(all.size(), 5u);
  EXPECT_EQ(all[0].frames, 3u);  // 1, 6, 11
  EXPECT_EQ(all[0].particles, 50u);
}

TEST_F(NnTraining, LatentsRefinedInParallelEqualThoseRefinedOneByOne) {
  nsf::NeuralModel m = nsf::NeuralModel::load(model());
  const nsf::Dataset d(data());
  const nsf::FrameLatentRefiner refiner(m, d.rest_positions(), 5);
  std::vector<nsf::FrameData> frames;
  std::vector<const float*> x;
  std::vector<Eigen::VectorXd> start, parallel;
  for (size_t k = 1; k <= 5; ++k) {
    frames.push_back(d.read_frame(d.test()[0], 2 * k));
    const torch::Tensor z =
        m.encode(torch::from_blob(frames.back().x.data(), {1, kParticles, 3})).to(torch::kFloat64);
    start.emplace_back(Eigen::Map<const Eigen::VectorXd>(z.data_ptr<double>(), z.size(1)));
  }
  for (const nsf::FrameData& f : frames) x.push_back(f.x.data());
  parallel = start;
  refiner.refine_many(x, parallel);  // five frames shared by the BLAS threads (2 in ctest)
  const nsf::ScopedBlasThreads one_blas_thread(1);
  auto same = [](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    return bit_identical({a.data(), a.data() + a.size()}, {b.data(), b.data() + b.size()});
  };
  for (size_t k = 0; k < frames.size(); ++k) {
    const Eigen::VectorXd alone = refiner.refine(x[k], start[k]);
    EXPECT_FALSE(same(alone, start[k])) << "frame " << k << ": nothing was refined";
    EXPECT_TRUE(same(alone, parallel[k])) << "frame " << k;
  }
  EXPECT_THROW(refiner.refine_many(x, start = {}), nsf::Error);
}

TEST(NnModelFile, KeepsTheEncoderShape) {
  nsf::NetConfig c = tiny_options().config.net;
  c.encoder_channels = 5;
  c.encoder_hidden = 24;
  c.encoder_max_length = 20;  // one convolution fewer than App. E's 12 for these particles
  nsf::NeuralModel m(c, nsf::SceneFingerprint{"shape", kParticles, 7}, false);
  m.rest = torch::zeros({kParticles, 3});  // the displacement form stores the rest shape
  const fs::path path = fs::temp_directory_path() / ("nsf_shape_" + std::to_string(::getpid()));
  m.save(path.string());
  const nsf::NeuralModel back = nsf::NeuralModel::load(path.string());
  fs::remove(path);
  EXPECT_EQ(back.config.encoder_channels, 5);
  EXPECT_EQ(back.config.encoder_hidden, 24);
  EXPECT_EQ(back.config.encoder_max_length, 20);
  EXPECT_EQ(back.encoder->conv_layers(), m.encoder->conv_layers());
  EXPECT_EQ(back.encoder->conv_layers(), nsf::Encoder(kParticles, c.latent_dim)->conv_layers() - 1);
  EXPECT_EQ(back.encoder->flat_length(), m.encoder->flat_length());
}

TEST_F(NnTraining, SaveAndReloadGiveBitIdenticalOutputs) {
  const std::vector<double> a = outputs(model(), data());
  nsf::NeuralModel m = nsf::NeuralModel::load(model());
  m.save(file("copy.nsf"));
  EXPECT_FALSE(fs::exists(file("copy.nsf.tmp")));
  EXPECT_TRUE(bit_identical(a, outputs(file("copy.nsf"), data())));
  EXPECT_TRUE(bit_identical(a, outputs(model(), data())));
}

TEST_F(NnTraining, ResumedTrainingEqualsUninterrupted) {
  const std::string out = file("resumed/synthetic.nsf");
  nsf::TrainOptions o = tiny_options();
  o.stop_after = 340;  // 40 steps into stage 2: resumes from its step-0 checkpoint
  const nsf::TrainReport first = nsf::train_model(data(), out, o);
  EXPECT_FALSE(first.completed);
  EXPECT_FALSE(fs::exists(out));
  ASSERT_TRUE(fs::exists(nsf::checkpoint_path_for(out)));
  o.stop_after = 60;  // interrupted again after the step-50 checkpoint: replays 10 steps
  nsf::train_model(data(), out, (o.resume = true, o));
  o.stop_after = -1;
  const nsf::TrainReport done = nsf::train_model(data(), out, o);
  ASSERT_TRUE(done.completed);
  EXPECT_EQ(done.stages[0].steps, 0);  // stage 1 was not repeated
  EXPECT_TRUE(bit_identical(outputs(model(), data()), outputs(out, data())));
  // The loss history survives the interruptions.
  EXPECT_EQ(read_losses(done.loss_csv).loss[2].size(), 200u);
}

TEST_F(NnTraining, CheckpointForOtherSettingsIsRejected) {
  const std::string out = file("other/synthetic.nsf");
  nsf::TrainOptions o = tiny_options();
  o.stop_after = 60;
  nsf::train_model(data(), out, o);
  o.config.seed = 99;
  o.resume = true;
  try {
    nsf::train_model(data(), out, o);
    FAIL() << "resumed a checkpoint written with another seed";
  } catch (const nsf::Error& e) {
    EXPECT_NE(std::string(e.what()).find("other settings"), std::string::npos) << e.what();
  }
}

TEST_F(NnTraining, ModelForAnotherSceneIsRejected) {
  // Same particle count, other rest positions (another sampling seed).
  const fs::path other = root_ / "other_scene";
  nsf::test::write_synthetic_dataset(other, kParticles, /*seed=*/8, /*frames=*/3);
  try {
    nsf::evaluate_model(model(), other.string(), {});
    FAIL() << "evaluated a model on another scene";
  } catch (const nsf::Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("trained for scene 'synthetic' (300 particles"), std::string::npos) << msg;
    EXPECT_NE(msg.find(other.string()), std::string::npos) << msg;
  }
  // Another particle count.
  const nsf::Particles few = nsf::test::synthetic_particles(kParticles - 1, 7);
  NeuralFields nf = NeuralFields::load(model());
  EXPECT_THROW(nf.check_scene("synthetic", few.X, "run"), nsf::Error);
  EXPECT_NO_THROW(
      nf.check_scene("synthetic", nsf::test::synthetic_particles(kParticles, 7).X, "run"));
}

TEST_F(NnTraining, ForeignOrMissingModelFileIsAClearError) {
  std::ofstream(file("junk.nsf")) << "not a model";
  EXPECT_THROW(NeuralFields::load(file("junk.nsf")), nsf::Error);
  EXPECT_THROW(NeuralFields::load(file("missing.nsf")), nsf::Error);
}

TEST_F(NnTraining, BatchedFieldsMatchPerPointCalls) {
  // One call over many points equals calls over single points: no cross-talk inside a batch,
  // and g at arbitrary X (resolution boost) works.
  NeuralFields nf = NeuralFields::load(model());
  const nsf::Dataset d(data());
  const Latent z = nf.encode(d.read_positions(d.train()[1], 7));
  ASSERT_EQ(z.size(), 2);
  std::vector<Vec3> X = d.rest_positions();
  X.push_back(Vec3(0.5, 0.5, 0.5));
  std::vector<Vec3> all, one;
  nf.deform(nf.prepare(X), z, all);
  ASSERT_EQ(all.size(), X.size());
  for (size_t p : {size_t(0), size_t(17), X.size() - 1}) {
    nf.deform(nf.prepare({X[p]}), z, one);
    EXPECT_LT((one[0] - all[p]).norm(), 1e-5);
  }
  std::vector<nsf::Mat3> tau;
  nf.stress(nf.prepare(X), z, 1.0, tau);
  for (const auto& t : tau) EXPECT_EQ(t, t.transpose());
  EXPECT_THROW(nf.encode(std::vector<Vec3>(10)), nsf::Error);
}
