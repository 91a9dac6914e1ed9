// Rigid frames over the latent manifold (rom/step/rigid_frames.h) on a synthetic deformation: the
// Jacobian of g in the frames against finite differences, the fit recovering a known latent and
// frame, τ turned with the frame, and the frames' errors.
// GCC 12 reports false -Wmaybe-uninitialized warnings from inside Eigen's AVX-512 kernels for
// dynamic-size matrices (in the intrinsics headers, not in this code).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "error_matchers.h"
#include "nn/latent_inversion.h"
#include "rom/step/rigid_frames.h"

using nsf::Latent;
using nsf::Mat3;
using nsf::Vec3;

namespace {

constexpr int kR = 3;  // the synthetic model's latent dimension

// g_p(ẑ) = X_p + A_p ẑ + 0.05 sin(ẑ_0) X_p: nonlinear in ẑ, with its exact Jacobian.
struct SyntheticG {
  std::vector<Vec3> X;
  std::vector<Eigen::Matrix<double, 3, kR>> A;
  Vec3 at(size_t p, const Latent& z) const {
    return X[p] + A[p] * z + 0.05 * std::sin(z[0]) * X[p];
  }
  Eigen::Matrix<double, 3, kR> d(size_t p, const Latent& z) const {
    Eigen::Matrix<double, 3, kR> J = A[p];
    J.col(0) += 0.05 * std::cos(z[0]) * X[p];
    return J;
  }
};

class SyntheticSamples final : public nsf::SampleDeformation {
 public:
  SyntheticSamples(const SyntheticG& g, std::vector<uint32_t> ids) : g_(g), ids_(std::move(ids)) {}
  size_t size() const override { return ids_.size(); }
  void evaluate(const Eigen::VectorXd& z, std::vector<Vec3>& x) override {
    x.resize(ids_.size());
    for (size_t k = 0; k < ids_.size(); ++k) x[k] = g_.at(ids_[k], z);
  }
  void jacobian(const Eigen::VectorXd& z, Eigen::MatrixXd& J, std::vector<Vec3>& x) override {
    evaluate(z, x);
    J.resize(3 * int64_t(ids_.size()), kR);
    for (size_t k = 0; k < ids_.size(); ++k) J.block(3 * int64_t(k), 0, 3, kR) = g_.d(ids_[k], z);
  }

 private:
  const SyntheticG& g_;
  std::vector<uint32_t> ids_;
};

class SyntheticSource final : public nsf::DeformationSource {
 public:
  explicit SyntheticSource(const SyntheticG& g) : g_(g) {}
  std::string describe() const override { return "x from a synthetic g"; }
  void positions(const std::vector<uint32_t>& ids, const Latent& z, const Latent&,
                 std::vector<Vec3>& x) override {
    x.resize(ids.size());
    for (size_t k = 0; k < ids.size(); ++k) x[k] = g_.at(ids[k], z);
  }
  std::unique_ptr<nsf::SampleDeformation> samples(const std::vector<uint32_t>& S) override {
    return std::make_unique<SyntheticSamples>(g_, S);
  }

 private:
  const SyntheticG& g_;
};

class ConstantField final : public nsf::PointFieldSource {
 public:
  explicit ConstantField(Mat3 value) : value_(std::move(value)) {}
  std::string describe() const override { return "tau constant"; }
  void evaluate(const std::vector<uint32_t>& ids, const nsf::LatentPair&, bool,
                std::vector<Mat3>& out) override {
    out.assign(ids.size(), value_);
  }

 private:
  Mat3 value_;
};

// Two objects of 20 particles each; object 1 is framed (frame 0), object 0 is not.
struct TwoObjects {
  SyntheticG g;
  std::vector<double> mass;
  std::vector<uint16_t> object;
  TwoObjects() {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int p = 0; p < 40; ++p) {
      g.X.push_back(Vec3(0.5 + 0.1 * u(rng), 0.5 + 0.1 * u(rng), 0.5 + 0.1 * u(rng)) +
                    (p >= 20 ? Vec3(0.3, 0, 0) : Vec3::Zero()));
      Eigen::Matrix<double, 3, kR> A;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < kR; ++j) A(i, j) = 0.05 * u(rng);
      g.A.push_back(A);
      mass.push_back(1 + 0.5 * u(rng));
      object.push_back(p >= 20 ? 1 : 0);
    }
  }
  nsf::RigidFrames frames() const { return nsf::make_rigid_frames(kR, {1}, g.X, mass, object); }
};

Latent latent(std::initializer_list<double> v) {
  Latent z(static_cast<int64_t>(v.size()));
  int64_t i = 0;
  for (double x : v) z[i++] = x;
  return z;
}

TEST(RigidFrames, PivotAboutEachFramedObjectsCentroidAndMoveOnlyItsPoints) {
  const TwoObjects s;
  const nsf::RigidFrames f = s.frames();
  ASSERT_EQ(f.frames, 1);
  EXPECT_EQ(f.dim(), kR + 6);
  Vec3 c = Vec3::Zero();
  double m = 0;
  for (size_t p = 20; p < 40; ++p) c += s.mass[p] * s.g.X[p], m += s.mass[p];
  EXPECT_LT((f.pivot[0] - c / m).norm(), 1e-12);
  // A quarter turn about z and a shift: object 1's points turn about its centroid, object 0's stay.
  Latent z = f.augment(latent({0.1, 0, 0}));
  z.segment<3>(kR) = Vec3(0, 0, M_PI / 2);
  z.segment<3>(kR + 3) = Vec3(0.01, 0.02, 0.03);
  std::vector<Vec3> x = s.g.X;
  f.apply(nullptr, z, x);
  for (size_t p = 0; p < 40; ++p) {
    const Vec3 d = s.g.X[p] - f.pivot[0];
    const Vec3 want =
        p < 20 ? s.g.X[p] : f.pivot[0] + Vec3(-d.y(), d.x(), d.z()) + Vec3(0.01, 0.02, 0.03);
    EXPECT_LT((x[p] - want).norm(), 1e-12) << p;
  }
  EXPECT_EQ(f.model(z), latent({0.1, 0, 0}));
}

// ∂/∂(ẑ, θ, t) of g in the frames against central differences, at a turn of almost two radians,
// where SO(3)'s left Jacobian is far from the identity.
TEST(RigidFrames, JacobianMatchesFiniteDifferences) {
  const TwoObjects s;
  const nsf::RigidFrames f = s.frames();
  auto g = nsf::in_rigid_frames(std::make_unique<SyntheticSource>(s.g), f);
  std::vector<uint32_t> S;
  for (uint32_t p = 0; p < 40; p += 3) S.push_back(p);
  auto gs = g->samples(S);
  Latent z = f.augment(latent({0.3, -0.2, 0.5}));
  z.segment<3>(kR) = Vec3(0.9, -1.1, 1.2);
  z.segment<3>(kR + 3) = Vec3(0.05, -0.02, 0.04);
  Eigen::MatrixXd J;
  std::vector<Vec3> at;
  gs->jacobian(z, J, at);
  ASSERT_EQ(J.cols(), f.dim());
  std::vector<Vec3> check;
  gs->evaluate(z, check);
  for (size_t k = 0; k < S.size(); ++k) EXPECT_LT((check[k] - at[k]).norm(), 1e-14);
  const double h = 1e-6;
  double worst = 0;
  for (int j = 0; j < f.dim(); ++j) {
    Latent zp = z, zm = z;
    zp[j] += h, zm[j] -= h;
    std::vector<Vec3> xp, xm;
    gs->evaluate(zp, xp);
    gs->evaluate(zm, xm);
    for (size_t k = 0; k < S.size(); ++k) {
      const Vec3 fd = (xp[k] - xm[k]) / (2 * h);
      worst = std::max(worst, (fd - J.block(3 * int64_t(k), j, 3, 1)).norm());
    }
  }
  EXPECT_LT(worst, 1e-7);
  // Unframed points have no frame columns.
  EXPECT_EQ(J.block(0, kR, 3, 6).norm(), 0.0);
}

// Gauss–Newton in the frames recovers a latent and a frame it did not start from, from the
// samples' positions alone.
TEST(RigidFrames, TheFitRecoversAKnownLatentAndFrame) {
  const TwoObjects s;
  const nsf::RigidFrames f = s.frames();
  auto g = nsf::in_rigid_frames(std::make_unique<SyntheticSource>(s.g), f);
  std::vector<uint32_t> S(40);
  for (uint32_t p = 0; p < 40; ++p) S[p] = p;
  auto gs = g->samples(S);
  Latent truth = f.augment(latent({0.2, -0.1, 0.15}));
  truth.segment<3>(kR) = Vec3(0.2, -0.3, 0.4);
  truth.segment<3>(kR + 3) = Vec3(0.03, -0.01, 0.02);
  std::vector<Vec3> target;
  gs->evaluate(truth, target);
  nsf::GaussNewtonOptions o;
  o.max_iterations = 30;
  o.tolerance = 1e-12;
  const nsf::InversionResult r =
      nsf::invert_deformation(*gs, target, f.augment(Latent::Zero(kR)), o);
  EXPECT_LT((r.z - truth).norm(), 1e-8) << r.z.transpose();
  EXPECT_LT(r.rms_residual, 1e-10);
  // Levenberg–Marquardt damping (rom.gn_damping) shortens each step but not where it ends.
  o.max_iterations = 1;
  const Latent start = f.augment(Latent::Zero(kR));
  const double plain_step = (nsf::invert_deformation(*gs, target, start, o).z - start).norm();
  o.damping = 0.5;
  const double damped_step = (nsf::invert_deformation(*gs, target, start, o).z - start).norm();
  EXPECT_LT(damped_step, 0.9 * plain_step);
  o.max_iterations = 100;
  EXPECT_LT((nsf::invert_deformation(*gs, target, start, o).z - truth).norm(), 1e-8);
}

// τ and C from the model turn with the frame; a tracked source's, whose state turned with the
// body, and an unframed object's do not.
TEST(RigidFrames, TheModelsFieldsTurnWithTheFrame) {
  const TwoObjects s;
  const nsf::RigidFrames f = s.frames();
  Mat3 tau;
  tau << 1, 2, 0, 2, 3, 0, 0, 0, 5;
  Latent z = f.augment(latent({0, 0, 0}));
  z.segment<3>(kR) = Vec3(0, 0, 0.7);
  const Mat3 R = Eigen::AngleAxisd(0.7, Vec3::UnitZ()).toRotationMatrix();
  const std::vector<uint32_t> ids = {3, 25};
  std::vector<Mat3> out;
  nsf::in_rigid_frames(std::make_unique<ConstantField>(tau), f, true)
      ->evaluate(ids, {z, z}, true, out);
  EXPECT_LT((out[0] - tau).norm(), 1e-12);
  EXPECT_LT((out[1] - R * tau * R.transpose()).norm(), 1e-12);
  nsf::in_rigid_frames(std::make_unique<ConstantField>(tau), f, false)
      ->evaluate(ids, {z, z}, true, out);
  EXPECT_LT((out[1] - tau).norm(), 1e-12);
}

TEST(RigidFrames, AnObjectTheSceneLacksIsAClearError) {
  const TwoObjects s;
  nsf::testing::expect_error([&] { nsf::make_rigid_frames(kR, {2}, s.g.X, s.mass, s.object); },
                             {"rigid_frames names object 2", "the scene has 2"});
  EXPECT_FALSE(nsf::make_rigid_frames(kR, {}, s.g.X, s.mass, s.object).on());
}

}  // namespace
