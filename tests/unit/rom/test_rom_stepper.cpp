// The reduced-order simulator's parts (§5) on an untrained model: the inversion, its Jacobian and
// the latent prior's pull, the networks' deformation gradient, and the MPM step on N. The runs on a
// trained model are unit/rom/eval/test_rom_end_to_end.cpp's.
// GCC 12 reports false -Wmaybe-uninitialized warnings from inside Eigen's AVX-512 kernels for
// dynamic-size matrices (in the intrinsics headers, not in this code).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include "mpm/simulation.h"
#include "nn/latent_inversion.h"
#include "nn/model/neural_model.h"
#include "nn/network_samples.h"
#include "rom/inversion/latent_prior.h"
#include "rom/step/integration_set.h"

namespace fs = std::filesystem;
using nsf::Vec3;

namespace {

const std::string kTinyScene =
    (fs::path(NSF_SOURCE_DIR) / "scenes" / "examples" / "rom_tiny.json").string();

// An untrained model over random rest positions: enough for the inversion's algebra.
struct RandomModel {
  nsf::NeuralModel model;
  std::vector<Vec3> X;
  torch::Tensor Xn;
  static nsf::NetConfig config() {
    nsf::NetConfig c;
    c.decoder = nsf::DecoderFamily::mlp;
    c.latent_dim = 4;
    c.depth = 3;
    c.width_g = c.width_h = c.width_l = 32;
    c.encoder_hidden = 8;
    return c;
  }
  // The same weights whatever ran before in the process (the initialisation draws from torch's
  // global generator).
  static nsf::NetConfig seeded_config() {
    torch::manual_seed(5);
    return config();
  }
  explicit RandomModel(int n)
      : model(seeded_config(), nsf::SceneFingerprint{"random", n, 1}, false) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int p = 0; p < n; ++p) X.emplace_back(u(rng), u(rng), u(rng));
    Xn = torch::from_blob(X.data()->data(), {n, 3}, torch::kFloat64).to(torch::kFloat32);
    model.set_eval_mode();
  }
  std::vector<Vec3> deform(const Eigen::VectorXd& z) {
    torch::NoGradGuard ng;
    const int64_t n = Xn.size(0);
    const torch::Tensor zt =
        torch::from_blob(const_cast<double*>(z.data()), {1, z.size()}, torch::kFloat64)
            .to(torch::kFloat32)
            .expand({n, z.size()});
    const torch::Tensor o = model.deform(Xn, zt).to(torch::kFloat64).contiguous();
    std::vector<Vec3> x(n);
    for (int64_t p = 0; p < n; ++p)
      x[p] = Vec3(o[p][0].item<double>(), o[p][1].item<double>(), o[p][2].item<double>());
    return x;
  }
};

TEST(RomInversion, RecoversAKnownLatentFromTheNetworksOwnOutput) {
  RandomModel m(40);
  Eigen::VectorXd z_true(4);
  z_true << 0.3, -0.7, 0.5, 0.1;
  const std::vector<Vec3> target = m.deform(z_true);
  Eigen::VectorXd z0 = z_true + Eigen::VectorXd::Constant(4, 0.2);
  nsf::GaussNewtonOptions opt;
  opt.max_iterations = 20;
  opt.tolerance = 1e-7;
  const nsf::InversionResult r = nsf::invert_deformation(m.model, m.Xn, target, z0, opt);
  EXPECT_LT((r.z - z_true).norm(), 1e-3) << r.z.transpose();
  // Float32 networks: the residual floor is a few ulps of the positions (~1).
  EXPECT_LT(r.rms_residual, 1e-4);
  // The positions it returns are g at the returned latent.
  const std::vector<Vec3> at_z = m.deform(r.z);
  ASSERT_EQ(r.fitted.size(), at_z.size());
  for (size_t p = 0; p < at_z.size(); ++p) EXPECT_LT((r.fitted[p] - at_z[p]).norm(), 1e-6);
  // Started far away, the line search never returns a latent that fits worse than the start.
  const Eigen::VectorXd far = z_true + Eigen::VectorXd::Constant(4, 3.0);
  opt.max_iterations = 2;
  const nsf::InversionResult f = nsf::invert_deformation(m.model, m.Xn, target, far, opt);
  double start = 0;
  const std::vector<Vec3> x_far = m.deform(far);
  for (size_t p = 0; p < target.size(); ++p) start += (x_far[p] - target[p]).squaredNorm();
  EXPECT_LE(f.rms_residual, std::sqrt(start / double(target.size())));
  // The first-order Taylor variant is one linearised step.
  opt.taylor = true;
  const nsf::InversionResult t = nsf::invert_deformation(m.model, m.Xn, target, z0, opt);
  EXPECT_EQ(t.iterations, 1);
}

// The latent prior adds nothing where the latent lies on the training runs' surface, and pulls a
// latent that lies off it toward it, the more the larger ε.
TEST(RomInversion, LatentPriorKeepsALatentOnTheTrainingSurfaceAndPullsOneOffItTowardIt) {
  RandomModel m(40);
  Eigen::VectorXd base(4), along_t(4), along_mu(4), normal(4);
  base << 0.1, -0.5, 0.3, 0.0;
  along_t << 0.2, 0.0, 0.1, 0.0;
  along_mu << 0.0, 0.15, 0.0, -0.1;
  normal << 0.0, 0.0, 0.0, 1.0;
  normal -= normal.dot(along_mu) / along_mu.squaredNorm() * along_mu;
  normal.normalize();
  std::vector<std::vector<Eigen::VectorXd>> runs(3);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 4; ++i) runs[size_t(j)].push_back(base + i * along_t + j * along_mu);
  const nsf::LatentPrior prior(runs, Eigen::VectorXd::Constant(4, 0.2));
  nsf::GaussNewtonOptions opt;
  opt.max_iterations = 30;
  opt.tolerance = 1e-8;
  opt.penalty = &prior;
  opt.penalty_length = 0.05;

  const Eigen::VectorXd on = base + 1.5 * along_t + 0.5 * along_mu;
  ASSERT_LT(prior.distance2(on), 1e-20);
  const nsf::InversionResult r = nsf::invert_deformation(
      m.model, m.Xn, m.deform(on), on + Eigen::VectorXd::Constant(4, 0.2), opt);
  EXPECT_LT((r.z - on).norm(), 1e-3) << r.z.transpose();

  const Eigen::VectorXd off = on + 0.3 * normal;
  const std::vector<Vec3> target = m.deform(off);
  const double d_off = std::sqrt(prior.distance2(off));
  ASSERT_GT(d_off, 0.5);
  double last = d_off;
  for (double eps : {0.001, 0.01, 0.1}) {
    opt.penalty_length = eps;
    const nsf::InversionResult p = nsf::invert_deformation(m.model, m.Xn, target, off, opt);
    const double d = std::sqrt(prior.distance2(p.z));
    EXPECT_LT(d, last) << "epsilon " << eps;
    last = d;
  }
  EXPECT_LT(last, 0.2 * d_off);
  // Without it (or ε = 0), the fit is the paper's: back to the latent that made the positions.
  opt.penalty_length = 0;
  const nsf::InversionResult plain = nsf::invert_deformation(m.model, m.Xn, target, on, opt);
  EXPECT_LT((plain.z - off).norm(), 1e-3) << plain.z.transpose();
}

TEST(RomInversion, JacobianMatchesFiniteDifferences) {
  RandomModel m(25);
  Eigen::VectorXd z(4);
  z << 0.2, 0.4, -0.3, 0.6;
  Eigen::MatrixXd J;
  std::vector<Vec3> g;
  nsf::deformation_jacobian(m.model, m.Xn, z, J, g);
  ASSERT_EQ(J.rows(), 75);
  ASSERT_EQ(J.cols(), 4);
  const double h = 1e-2;  // float32 networks: central differences need a large step
  double worst = 0, scale = J.cwiseAbs().maxCoeff();
  for (int k = 0; k < 4; ++k) {
    Eigen::VectorXd zp = z, zm = z;
    zp[k] += h, zm[k] -= h;
    const auto xp = m.deform(zp), xm = m.deform(zm);
    for (size_t p = 0; p < xp.size(); ++p)
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::abs((xp[p][c] - xm[p][c]) / (2 * h) - J(3 * p + c, k)));
  }
  EXPECT_GT(scale, 1e-3);  // the network does depend on z
  EXPECT_LT(worst, 2e-3 * scale + 1e-4) << "max |J - FD| = " << worst;
}

// The engine half of §5.2: with identical particle states, an MPM step over N (and G2P over S)
// moves S exactly as a full step over every particle does.
TEST(RomFieldGradients, DeformationGradientMatchesFiniteDifferences) {
  RandomModel m(12);
  Eigen::VectorXd z(4);
  z << 0.4, -0.2, 0.1, 0.6;
  const torch::Tensor zt = torch::from_blob(z.data(), {1, 4}, torch::kFloat64)
                               .to(torch::kFloat32)
                               .expand({m.Xn.size(0), 4});
  const torch::Tensor F = nsf::deformation_gradients(m.model, m.Xn, zt);
  ASSERT_EQ(F.size(0), 12);
  const torch::Tensor sigma = m.model.norm_X.std.to(torch::kFloat64);
  const double h = 1e-2;  // in normalised units; float32 networks
  for (int a = 0; a < 3; ++a) {
    torch::Tensor dX = torch::zeros({1, 3});
    dX[0][a] = h;
    const torch::NoGradGuard no_grad;
    const torch::Tensor xp = m.model.deform(m.Xn + dX, zt).to(torch::kFloat64);
    const torch::Tensor xm = m.model.deform(m.Xn - dX, zt).to(torch::kFloat64);
    // Column a of F: ∂x/∂X_a = ∂x/∂Xn_a / σ_a.
    const torch::Tensor fd = (xp - xm) / (2 * h * sigma[a].item<double>());
    const torch::Tensor col = F.select(2, a);
    EXPECT_LT((fd - col).abs().max().item<double>(), 2e-3 * (1 + col.abs().max().item<double>()))
        << "column " << a;
  }
}

TEST(RomMpmStep, StepOnIntegrationParticlesGivesTheFullStepsSamplePositions) {
  nsf::Simulation full(nsf::load_scene(kTinyScene));
  for (int i = 0; i < 120; ++i) full.step();  // in contact with the floor, deformed
  const nsf::Particles state = full.particles();
  const double t = full.time(), dt = full.settings().dt;

  std::vector<uint32_t> S;  // a few particles at one end of the bar, so N is a proper subset
  for (uint32_t p = 0; p < state.size(); p += 5)
    if (state.X[p].x() < 0.3) S.push_back(p);
  const nsf::Grid& grid = full.grid();
  nsf::NodeMarks I(grid.lo(), grid.dx(), grid.dims());
  std::vector<Vec3> xs;
  for (uint32_t p : S) xs.push_back(state.x[p]);
  I.mark_stencils(xs);
  const std::vector<uint32_t> N = nsf::integration_particles(I, state.x);
  ASSERT_LT(N.size(), state.size()) << "the test needs N to be a proper subset";
  ASSERT_GT(N.size(), S.size());

  nsf::Simulation rom(nsf::load_scene(kTinyScene));
  nsf::Particles& P = rom.particles();
  P = nsf::Particles{};
  std::vector<uint32_t> gather;
  for (uint32_t p : N) {
    P.add(state.X[p], state.v[p], state.mass[p], state.vol0[p], state.mat[p], state.material[p], 0);
    P.x.back() = state.x[p], P.C.back() = state.C[p], P.F.back() = state.F[p];
    P.tau.back() = state.tau[p];
    if (std::find(S.begin(), S.end(), p) != S.end()) gather.push_back(uint32_t(P.size() - 1));
  }
  ASSERT_EQ(gather.size(), S.size());
  rom.transfer(dt, t, &gather);
  full.step();
  for (size_t k = 0; k < S.size(); ++k)
    EXPECT_EQ(P.x[gather[k]], full.particles().x[S[k]]) << "sample particle " << S[k];
}

}  // namespace
