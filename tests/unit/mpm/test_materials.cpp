// Constitutive models of App. F against values computed by hand from the paper's formulas.
// Parameters throughout: E = 1000, ν = 0.3, so μ = 1000/2.6 and λ = 300/0.52.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/svd3.h"
#include "mpm/materials/material.h"

namespace {

using nsf::Mat3;
using nsf::MaterialPoint;
using nsf::ParamMap;
using nsf::Vec3;

const double kE = 1000.0, kNu = 0.3;
const double kMu = 1000.0 / (2.0 * 1.3);
const double kLambda = 1000.0 * 0.3 / (1.3 * 0.4);
const char* kPath = "objects[0].material";

Mat3 rot(double angle, const Vec3& axis) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}
const Mat3 kRa = rot(0.7, Vec3(1, 2, 3));
const Mat3 kRb = rot(-1.3, Vec3(-2, 0.5, 1));

Mat3 diag(double a, double b, double c) {
  return Vec3(a, b, c).asDiagonal();
}

// Largest entry of |A − B| relative to max(‖B‖, 1): the stresses here are O(10..1000).
double rel_err(const Mat3& A, const Mat3& B) {
  return (A - B).cwiseAbs().maxCoeff() / std::max(B.norm(), 1.0);
}

struct Model {
  std::unique_ptr<nsf::Material> m;
  MaterialPoint mp;
  Model(const std::string& type, const ParamMap& params)
      : m(nsf::make_material(type)), mp(m->make_point(params, kPath)) {}
  // Returns τ and updates F in place, like the engine does.
  Mat3 update(Mat3& F, double dt = 1e-3) { return m->update(F, mp, dt); }
  Mat3 stress(Mat3 F) { return update(F); }
};

Mat3 dev(const Mat3& A) {
  return A - A.trace() / 3.0 * Mat3::Identity();
}

// log of the (positive) principal stretches of F = Ra diag(·) Rbᵀ, read back in that frame.
Vec3 log_stretches_in_frame(const Mat3& F) {
  Mat3 D = kRa.transpose() * F * kRb;
  return Vec3(std::log(D(0, 0)), std::log(D(1, 1)), std::log(D(2, 2)));
}
double off_diagonal_in_frame(const Mat3& F) {
  Mat3 D = kRa.transpose() * F * kRb;
  D.diagonal().setZero();
  return D.cwiseAbs().maxCoeff();
}
Vec3 unit_dev(const Vec3& e) {
  Vec3 h = e - Vec3::Constant(e.mean());
  return h / h.norm();
}

// Objectivity and isotropy, for elastic and plastic states alike: τ(QF) = Q τ Qᵀ with
// F^E(QF) = Q F^E(F); τ(FQ) = τ(F) with F^E(FQ) = F^E(F) Q.
void expect_rotation_invariant(const std::string& type, const ParamMap& params, const Mat3& F) {
  const Mat3 Q = rot(2.1, Vec3(0.3, -1, 0.4));
  Model a(type, params), b(type, params), c(type, params);
  Mat3 F1 = F, F2 = Q * F, F3 = F * Q;
  Mat3 t1 = a.update(F1), t2 = b.update(F2), t3 = c.update(F3);
  EXPECT_LT(rel_err(t2, Q * t1 * Q.transpose()), 1e-12) << type;
  EXPECT_LT(rel_err(t3, t1), 1e-12) << type;
  EXPECT_LT((F2 - Q * F1).norm(), 1e-12) << type;
  EXPECT_LT((F3 - F1 * Q).norm(), 1e-12) << type;
  EXPECT_NEAR(a.mp.yield_stress, b.mp.yield_stress, 1e-12 * (1 + a.mp.yield_stress)) << type;
  EXPECT_LT((t1 - t1.transpose()).norm(), 1e-12 * (1 + t1.norm())) << type;
}

// ---------------------------------------------------------------------------------------------
// Registry and parameter validation

TEST(Registry, KnowsEveryBuiltinModel) {
  for (const char* t :
       {"fixed_corotated", "stvk_hencky", "drucker_prager", "von_mises", "herschel_bulkley"})
    EXPECT_NO_THROW(nsf::make_material(t)) << t;
}

struct ParamCase {
  std::string type;
  ParamMap valid;
  std::vector<std::string> required;
  std::vector<std::pair<std::string, double>> out_of_range;
};

std::string error_of(const std::string& type, const ParamMap& params) {
  try {
    nsf::make_material(type)->make_point(params, kPath);
  } catch (const nsf::Error& e) {
    return e.what();
  }
  return "";
}

TEST(MaterialParams, ErrorsNameTheKey) {
  const std::vector<std::pair<std::string, double>> elastic_bad = {
      {"E", 0.0}, {"E", -5.0}, {"nu", 0.5}, {"nu", 0.7}, {"nu", -1.0}};
  auto with = [](std::vector<std::pair<std::string, double>> v,
                 std::vector<std::pair<std::string, double>> more) {
    v.insert(v.end(), more.begin(), more.end());
    return v;
  };
  const std::vector<ParamCase> cases = {
      {"fixed_corotated", {{"E", kE}, {"nu", kNu}}, {"E", "nu"}, elastic_bad},
      {"stvk_hencky", {{"E", kE}, {"nu", kNu}}, {"E", "nu"}, elastic_bad},
      {"drucker_prager",
       {{"E", kE}, {"nu", kNu}, {"friction_angle", 30.0}},
       {"E", "nu", "friction_angle"},
       with(elastic_bad, {{"friction_angle", 0.0},
                          {"friction_angle", 90.0},
                          {"friction_angle", -10.0},
                          {"cohesion", -0.1}})},
      {"von_mises",
       {{"E", kE}, {"nu", kNu}, {"yield_stress", 50.0}},
       {"E", "nu", "yield_stress"},
       with(elastic_bad, {{"yield_stress", 0.0}, {"hardening", -1.0}, {"softening", -1.0}})},
      {"herschel_bulkley",
       {{"E", kE}, {"nu", kNu}, {"yield_stress", 20.0}, {"viscosity", 1.0}},
       {"E", "nu", "yield_stress", "viscosity"},
       with(elastic_bad, {{"yield_stress", -1.0}, {"viscosity", -1.0}})},
  };
  for (const auto& c : cases) {
    EXPECT_EQ(error_of(c.type, c.valid), "") << c.type;

    ParamMap typo = c.valid;
    typo["youngs_modulus"] = 1.0;
    EXPECT_NE(error_of(c.type, typo).find("objects[0].material.youngs_modulus"), std::string::npos)
        << c.type << ": " << error_of(c.type, typo);

    for (const auto& key : c.required) {
      ParamMap missing = c.valid;
      missing.erase(key);
      std::string msg = error_of(c.type, missing);
      EXPECT_NE(msg.find("'objects[0].material." + key + "'"), std::string::npos)
          << c.type << " without " << key << ": " << msg;
    }
    for (const auto& [key, value] : c.out_of_range) {
      ParamMap bad = c.valid;
      bad[key] = value;
      std::string msg = error_of(c.type, bad);
      EXPECT_NE(msg.find("'objects[0].material." + key + "'"), std::string::npos)
          << c.type << " with " << key << " = " << value << ": " << msg;
    }
  }
}

TEST(MaterialParams, LameParametersFromYoungAndPoisson) {
  Model m("fixed_corotated", {{"E", kE}, {"nu", kNu}});
  EXPECT_NEAR(m.mp.mu, 384.61538461538464, 1e-10);
  EXPECT_NEAR(m.mp.lambda, 576.9230769230769, 1e-10);
}

// ---------------------------------------------------------------------------------------------
// F.1 fixed corotated: τ = 2μ(F − R)Fᵀ + λ(J − 1)J I

TEST(FixedCorotated, ZeroStressAtIdentity) {
  Model m("fixed_corotated", {{"E", kE}, {"nu", kNu}});
  EXPECT_LT(m.stress(Mat3::Identity()).norm(), 1e-12);
}

TEST(FixedCorotated, DiagonalStretchByHand) {
  Model m("fixed_corotated", {{"E", kE}, {"nu", kNu}});
  // R = I, J = 1.1·0.9·1.0 = 0.99.
  const double vol = kLambda * (0.99 - 1.0) * 0.99;
  Mat3 expected = diag(2 * kMu * 0.1 * 1.1 + vol, 2 * kMu * (-0.1) * 0.9 + vol, vol);
  EXPECT_LT(rel_err(m.stress(diag(1.1, 0.9, 1.0)), expected), 1e-14);
}

TEST(FixedCorotated, RotatedStretchByHand) {
  Model m("fixed_corotated", {{"E", kE}, {"nu", kNu}});
  // F = Ra Σ Rbᵀ, R = Ra Rbᵀ: (F − R)Fᵀ = Ra (Σ − 1)Σ Raᵀ, J = 1.2·0.8·1.05 = 1.008.
  const double vol = kLambda * (1.008 - 1.0) * 1.008;
  Mat3 principal =
      diag(2 * kMu * 0.2 * 1.2 + vol, 2 * kMu * (-0.2) * 0.8 + vol, 2 * kMu * 0.05 * 1.05 + vol);
  Mat3 F = kRa * diag(1.2, 0.8, 1.05) * kRb.transpose();
  EXPECT_LT(rel_err(m.stress(F), kRa * principal * kRa.transpose()), 1e-13);
}

TEST(FixedCorotated, InvertedUsesSignedSingularValue) {
  Model m("fixed_corotated", {{"E", kE}, {"nu", kNu}});
  // det F < 0: R must stay a rotation (R = I here), J = −0.96 < 0.
  const double J = 1.2 * 1.0 * -0.8;
  const double vol = kLambda * (J - 1.0) * J;
  Mat3 expected = diag(2 * kMu * 0.2 * 1.2 + vol, vol, 2 * kMu * (-1.8) * (-0.8) + vol);
  EXPECT_LT(rel_err(m.stress(diag(1.2, 1.0, -0.8)), expected), 1e-14);
}

TEST(FixedCorotated, RotationInvariant) {
  expect_rotation_invariant("fixed_corotated", {{"E", kE}, {"nu", kNu}},
                            kRa * diag(1.3, 0.7, 0.95) * kRb.transpose());
}

// ---------------------------------------------------------------------------------------------
// F.2 StVK-Hencky: τ = U (2μ ε + λ sum(ε) 1) Uᵀ, ε = log Σ

TEST(StvkHencky, ZeroStressAtIdentity) {
  Model m("stvk_hencky", {{"E", kE}, {"nu", kNu}});
  EXPECT_LT(m.stress(Mat3::Identity()).norm(), 1e-12);
}

TEST(StvkHencky, DiagonalStretchByHand) {
  Model m("stvk_hencky", {{"E", kE}, {"nu", kNu}});
  const double e0 = std::log(1.1), e1 = std::log(0.9), tr = e0 + e1;
  Mat3 expected = diag(2 * kMu * e0 + kLambda * tr, 2 * kMu * e1 + kLambda * tr, kLambda * tr);
  EXPECT_LT(rel_err(m.stress(diag(1.1, 0.9, 1.0)), expected), 1e-14);
}

TEST(StvkHencky, StressLivesInLeftFrame) {
  // Different left and right rotations: U(…)Vᵀ (eq. 13 as printed) would be non-symmetric;
  // the Kirchhoff stress of the Hencky energy is Ra(…)Raᵀ.
  Model m("stvk_hencky", {{"E", kE}, {"nu", kNu}});
  const double e0 = std::log(1.2), e1 = std::log(0.8), e2 = std::log(1.05), tr = e0 + e1 + e2;
  Mat3 principal =
      diag(2 * kMu * e0 + kLambda * tr, 2 * kMu * e1 + kLambda * tr, 2 * kMu * e2 + kLambda * tr);
  Mat3 tau = m.stress(kRa * diag(1.2, 0.8, 1.05) * kRb.transpose());
  EXPECT_LT(rel_err(tau, kRa * principal * kRa.transpose()), 1e-13);
}

TEST(StvkHencky, PureDilationIsIsotropic) {
  Model m("stvk_hencky", {{"E", kE}, {"nu", kNu}});
  const double p = (2 * kMu + 3 * kLambda) * std::log(1.1);
  EXPECT_LT(rel_err(m.stress(kRa * (1.1 * Mat3::Identity())), p * Mat3::Identity()), 1e-14);
}

TEST(StvkHencky, RotationInvariant) {
  expect_rotation_invariant("stvk_hencky", {{"E", kE}, {"nu", kNu}},
                            kRa * diag(1.3, 0.7, 0.95) * kRb.transpose());
}

// ---------------------------------------------------------------------------------------------
// F.3 Drucker–Prager

const ParamMap kSand = {{"E", kE}, {"nu", kNu}, {"friction_angle", 30.0}};
// α for φ = 30°: sin φ = 1/2.
const double kAlpha30 = std::sqrt(2.0 / 3.0) * 2.0 * 0.5 / (3.0 - 0.5);

// The cone ‖dev τ‖ + α tr τ ≤ 0, relative to ‖τ‖.
double cone(const Mat3& tau, double alpha) {
  return dev(tau).norm() + alpha * tau.trace();
}

TEST(DruckerPrager, AlphaFromFrictionAngle) {
  Model m("drucker_prager", kSand);
  EXPECT_NEAR(m.mp.alpha, kAlpha30, 1e-15);
  EXPECT_EQ(m.mp.cohesion, 0.0);
}

TEST(DruckerPrager, ZeroStressAtIdentity) {
  Model m("drucker_prager", kSand);
  Mat3 F = Mat3::Identity();
  EXPECT_LT(m.update(F).norm(), 1e-12);
  EXPECT_LT((F - Mat3::Identity()).norm(), 1e-14);
}

TEST(DruckerPrager, ExpansionProjectsToTip) {
  Model m("drucker_prager", kSand);
  Mat3 F = kRa * diag(1.1, 1.05, 0.98) * kRb.transpose();  // sum(ε) > 0
  Mat3 tau = m.update(F);
  EXPECT_EQ(tau, Mat3::Zero());
  EXPECT_LT((F - kRa * kRb.transpose()).norm(), 1e-13);
}

TEST(DruckerPrager, CohesionShiftsTheTip) {
  ParamMap p = kSand;
  p["cohesion"] = 0.01;
  Model m("drucker_prager", p);
  Mat3 F = kRa * diag(1.1, 1.05, 1.02) * kRb.transpose();  // sum(ε) = 0.164 > 3·0.01
  Mat3 tau = m.update(F);
  EXPECT_LT((F - std::exp(0.01) * kRa * kRb.transpose()).norm(), 1e-13);
  // Hencky stress of the isotropic stretch e^0.01: (2μ + 3λ)·0.01 on the diagonal.
  EXPECT_LT(rel_err(tau, (2 * kMu + 3 * kLambda) * 0.01 * Mat3::Identity()), 1e-13);
}

TEST(DruckerPrager, InsideConeIsUntouched) {
  Model m("drucker_prager", kSand);
  // Compression with little shear: ‖ε̂‖ ≈ 0.017, α(3λ+2μ)/2μ·tr ε ≈ −0.13, so δγ < 0.
  const Mat3 F0 = kRa * diag(0.95, 0.96, 0.97) * kRb.transpose();
  Mat3 F = F0;
  Mat3 tau = m.update(F);
  EXPECT_EQ(F, F0);
  const double e0 = std::log(0.95), e1 = std::log(0.96), e2 = std::log(0.97);
  const double tr = e0 + e1 + e2;
  Mat3 principal =
      diag(2 * kMu * e0 + kLambda * tr, 2 * kMu * e1 + kLambda * tr, 2 * kMu * e2 + kLambda * tr);
  EXPECT_LT(rel_err(tau, kRa * principal * kRa.transpose()), 1e-13);
  EXPECT_LT(cone(tau, kAlpha30), 0.0);
}

TEST(DruckerPrager, ShearProjectsOntoCone) {
  Model m("drucker_prager", kSand);
  // ε = log(1.2, 0.8, 0.9): tr ε = −0.146, ‖ε̂‖ = 0.296, δγ ≈ 0.14 > 0.
  const Mat3 F0 = kRa * diag(1.2, 0.8, 0.9) * kRb.transpose();
  Mat3 F = F0;
  Mat3 tau = m.update(F);
  EXPECT_GT((F - F0).norm(), 1e-2);                             // it did project
  EXPECT_LT(std::abs(cone(tau, kAlpha30)), 1e-9 * tau.norm());  // onto the cone
  EXPECT_NEAR(F.determinant(), F0.determinant(), 1e-12);        // keeping tr ε
  EXPECT_LT(off_diagonal_in_frame(F), 1e-12);                   // and U, V
  const Vec3 trial(std::log(1.2), std::log(0.8), std::log(0.9));
  EXPECT_LT((unit_dev(log_stretches_in_frame(F)) - unit_dev(trial)).norm(), 1e-12);  // and ε̂/‖ε̂‖
  EXPECT_LT(rel_err(tau, Model("stvk_hencky", {{"E", kE}, {"nu", kNu}}).stress(F)), 1e-13);
}

TEST(DruckerPrager, ProjectedStateIsAFixedPoint) {
  Model m("drucker_prager", kSand);
  Mat3 F = kRa * diag(1.2, 0.8, 0.9) * kRb.transpose();
  Mat3 tau1 = m.update(F);
  const Mat3 F1 = F;
  Mat3 tau2 = m.update(F);
  EXPECT_LT((F - F1).norm(), 1e-12);
  EXPECT_LT(rel_err(tau2, tau1), 1e-12);
}

TEST(DruckerPrager, RotationInvariant) {
  expect_rotation_invariant("drucker_prager", kSand,
                            kRa * diag(0.95, 0.96, 0.97) * kRb.transpose());
  expect_rotation_invariant("drucker_prager", kSand, kRa * diag(1.2, 0.8, 0.9) * kRb.transpose());
}

// ---------------------------------------------------------------------------------------------
// F.4 von Mises with hardening and softening

const double kTauY = 50.0;
ParamMap metal(double hardening = 0.0, double softening = 0.0) {
  return {{"E", kE},
          {"nu", kNu},
          {"yield_stress", kTauY},
          {"hardening", hardening},
          {"softening", softening}};
}
// δγ = ‖ε̂‖ − τ_y/2μ for the trial F = Ra diag(1.2, 0.85, 1.0) Rbᵀ.
double delta_gamma_trial(double tau_y) {
  const double e0 = std::log(1.2), e1 = std::log(0.85), m = (e0 + e1) / 3.0;
  const double norm = std::sqrt((e0 - m) * (e0 - m) + (e1 - m) * (e1 - m) + m * m);
  return norm - tau_y / (2.0 * kMu);
}
const Mat3 kShear = kRa * diag(1.2, 0.85, 1.0) * kRb.transpose();

TEST(VonMises, ZeroStressAtIdentity) {
  Model m("von_mises", metal());
  EXPECT_LT(m.stress(Mat3::Identity()).norm(), 1e-12);
}

TEST(VonMises, InsideCylinderIsUntouched) {
  Model m("von_mises", metal(0.1, 10.0));
  // 2μ‖ε̂‖ ≈ 11 < τ_y = 50.
  const Mat3 F0 = diag(1.01, 0.99, 1.0);
  Mat3 F = F0;
  Mat3 tau = m.update(F);
  EXPECT_EQ(F, F0);
  EXPECT_EQ(m.mp.yield_stress, kTauY);
  const double e0 = std::log(1.01), e1 = std::log(0.99), tr = e0 + e1;
  EXPECT_LT(
      rel_err(tau, diag(2 * kMu * e0 + kLambda * tr, 2 * kMu * e1 + kLambda * tr, kLambda * tr)),
      1e-13);
}

TEST(VonMises, ProjectsOntoCylinder) {
  Model m("von_mises", metal());
  Mat3 F = kShear;
  Mat3 tau = m.update(F);
  EXPECT_GT(delta_gamma_trial(kTauY), 0.1);
  EXPECT_NEAR(dev(tau).norm(), kTauY, 1e-9 * kTauY);
  EXPECT_NEAR(F.determinant(), kShear.determinant(), 1e-12);
  EXPECT_LT(off_diagonal_in_frame(F), 1e-12);
  const Vec3 trial(std::log(1.2), std::log(0.85), 0.0);
  EXPECT_LT((unit_dev(log_stretches_in_frame(F)) - unit_dev(trial)).norm(), 1e-12);
  EXPECT_EQ(m.mp.yield_stress, kTauY);  // no hardening, no softening
}

TEST(VonMises, HardeningRaisesYieldStress) {
  Model m("von_mises", metal(0.2));
  Mat3 F = kShear;
  Mat3 tau = m.update(F);
  EXPECT_NEAR(dev(tau).norm(), kTauY, 1e-9 * kTauY);  // projected with the old τ_y
  EXPECT_NEAR(m.mp.yield_stress, kTauY + 2 * kMu * 0.2 * delta_gamma_trial(kTauY), 1e-10);
  EXPECT_EQ(m.mp.damaged, 0.0);
}

TEST(VonMises, SofteningLowersYieldStressThenDamages) {
  const double theta = 100.0;
  Model m("von_mises", metal(0.0, theta));
  Mat3 F = kShear;
  m.update(F);
  EXPECT_NEAR(m.mp.yield_stress, kTauY - theta * delta_gamma_trial(kTauY), 1e-10);

  // Keep shearing: τ_y keeps falling until it reaches zero and the particle is damaged.
  const Mat3 step = kRa * diag(1.05, 1.0 / 1.05, 1.0) * kRa.transpose();
  double previous = m.mp.yield_stress;
  int steps = 0;
  while (m.mp.damaged == 0.0 && steps < 100) {
    F = step * F;
    m.update(F);
    EXPECT_LT(m.mp.yield_stress, previous);
    previous = m.mp.yield_stress;
    ++steps;
  }
  ASSERT_EQ(m.mp.damaged, 1.0) << "never damaged";
  EXPECT_EQ(m.mp.yield_stress, 0.0);
  EXPECT_EQ(m.mp.mu, 0.0);
  EXPECT_EQ(m.mp.lambda, 0.0);
  EXPECT_EQ(nsf::Material::p_wave_modulus(m.mp), 0.0);

  // Thereafter no stress, whatever the deformation.
  for (const Mat3& G : {Mat3(Mat3::Identity()), kShear, Mat3(diag(2.0, 0.3, 1.5))}) {
    Mat3 H = G;
    EXPECT_EQ(m.update(H), Mat3::Zero());
  }
}

TEST(VonMises, RotationInvariant) {
  expect_rotation_invariant("von_mises", metal(0.1, 5.0), diag(1.01, 0.99, 1.0));
  expect_rotation_invariant("von_mises", metal(0.1, 5.0), kShear);
}

// ---------------------------------------------------------------------------------------------
// F.5 Herschel–Bulkley: τ = κ/2 (J² − 1) I + μ dev(J^(−2/3) b), yield ‖dev τ‖ ≤ √(2/3) σ_Y

const double kKappa = 1000.0 / (3.0 * (1.0 - 2.0 * 0.3));
const double kSigmaY = 20.0;
const double kDt = 1e-3;
ParamMap paste(double viscosity, double sigma_y = kSigmaY) {
  return {{"E", kE}, {"nu", kNu}, {"yield_stress", sigma_y}, {"viscosity", viscosity}};
}

// The formula in matrix form, independent of the model's principal-space code.
Mat3 hb_stress(const Mat3& F) {
  const double J = F.determinant();
  const Mat3 b_bar = std::pow(J * J, -1.0 / 3.0) * F * F.transpose();
  return kKappa / 2.0 * (J * J - 1.0) * Mat3::Identity() + kMu * dev(b_bar);
}

TEST(HerschelBulkley, ZeroStressAtIdentity) {
  Model m("herschel_bulkley", paste(1.0));
  EXPECT_LT(m.stress(Mat3::Identity()).norm(), 1e-12);
}

TEST(HerschelBulkley, ElasticStressByHand) {
  Model m("herschel_bulkley", paste(1.0, 1e6));
  const double J = 0.99, scale = std::pow(J, -2.0 / 3.0);
  const double b0 = scale * 1.21, b1 = scale * 0.81, b2 = scale * 1.0;
  const double mean = (b0 + b1 + b2) / 3.0, p = kKappa / 2.0 * (J * J - 1.0);
  Mat3 expected = diag(p + kMu * (b0 - mean), p + kMu * (b1 - mean), p + kMu * (b2 - mean));
  Mat3 F = diag(1.1, 0.9, 1.0);
  EXPECT_LT(rel_err(m.update(F), expected), 1e-13);
  EXPECT_EQ(F, diag(1.1, 0.9, 1.0));
}

// s = s^tr − (s^tr − √(2/3)σ_Y)/(1 + η/2μΔt) for η = 0 (on the yield surface), η = 2μΔt (half
// way) and η = 10⁴·2μΔt (barely changes).
TEST(HerschelBulkley, ViscousReturnFollowsF5) {
  const double s_trial = dev(hb_stress(kShear)).norm();
  const double s_yield = std::sqrt(2.0 / 3.0) * kSigmaY;
  ASSERT_GT(s_trial, 2 * s_yield);
  for (double ratio : {0.0, 1.0, 1e4}) {
    const double eta = ratio * 2.0 * kMu * kDt;
    Model m("herschel_bulkley", paste(eta));
    Mat3 F = kShear;
    Mat3 tau = m.update(F, kDt);
    const double expected = s_trial - (s_trial - s_yield) / (1.0 + ratio);
    EXPECT_NEAR(dev(tau).norm(), expected, 1e-9 * expected) << "η/2μΔt = " << ratio;
    EXPECT_NEAR(F.determinant(), kShear.determinant(), 1e-12) << "volume kept";
    Mat3 R, S;
    nsf::polar3(F, R, S);
    EXPECT_LT((R - kRa * kRb.transpose()).norm(), 1e-12) << "rotation kept";
    EXPECT_LT(off_diagonal_in_frame(F), 1e-12);
    EXPECT_LT(rel_err(tau, hb_stress(F)), 1e-12) << "τ = τ(F^E)";
    if (ratio == 1e4) {
      EXPECT_LT((F - kShear).norm(), 1e-3 * kShear.norm());
    }
  }
}

TEST(HerschelBulkley, BelowYieldIsUntouched) {
  Model m("herschel_bulkley", paste(0.0, 1e3));
  Mat3 F = kShear;
  m.update(F);
  EXPECT_EQ(F, kShear);
}

TEST(HerschelBulkley, RotationInvariant) {
  expect_rotation_invariant("herschel_bulkley", paste(0.5), kShear);
  expect_rotation_invariant("herschel_bulkley", paste(0.5, 1e4), kShear);
}

}  // namespace
