// The tracked state of the integration points (rom/step/tracked_particles.h): a merged quadrature
// point starts from its group's state and stands for its members, the state cannot be renumbered
// once the run has begun, a plastic material's state remembers its path where an elastic one's
// does not, and a guard's rollback puts back the state of the newest mark.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "error_matchers.h"
#include "mpm/materials/material.h"
#include "mpm/particles.h"
#include "rom/fields/field_source.h"
#include "rom/step/tracked_particles.h"

namespace {

using nsf::Mat3;

constexpr double kE = 1e4, kNu = 0.3;

struct Materials {
  std::vector<std::unique_ptr<nsf::Material>> materials;
  std::vector<nsf::MaterialPoint> mat0;
  std::vector<uint16_t> material;
};

// n particles of one material.
Materials one_material(const std::string& type, const nsf::ParamMap& params, size_t n) {
  Materials s;
  s.materials.push_back(nsf::make_material(type));
  s.mat0.assign(n, s.materials[0]->make_point(params, "materials[0]"));
  s.material.assign(n, 0);
  return s;
}

Mat3 stretch(double a) {
  Mat3 F = Mat3::Identity();
  F(0, 0) = a;
  return F;
}

// One G2P's worth of new F (and a velocity) for point 0, as the step hands it over.
void advance_to(nsf::TrackedParticles& t, const Mat3& F) {
  nsf::Particles P;
  P.F = {F};
  P.C = {Mat3::Zero()};
  P.v = {nsf::Vec3(0.5, 0, 0)};
  t.advance({0}, P, {0});
}

TEST(TrackedParticles, AMergedPointStartsFromItsGroupAndStandsForItsMembers) {
  Materials s = one_material("stvk_hencky", {{"E", kE}, {"nu", kNu}}, 4);
  const std::vector<Mat3> F0 = {Mat3::Identity(), stretch(1.01), stretch(1.02), stretch(1.04)};
  nsf::TrackedParticles t(F0, s.mat0, s.material, s.materials, 1e-3);
  t.enlist("--stress tracked", true);
  // Particles 2 and 3 merged into point 4, a quarter and three quarters of its mass.
  nsf::PointTable table;
  table.particles = 4;
  table.X.resize(5, nsf::Vec3::Zero());
  table.material.assign(5, 0);
  table.mat0.assign(5, s.mat0[0]);
  table.merged_members = {{{2, 0.25}, {3, 0.75}}};
  t.set_points(table);
  EXPECT_TRUE(t.F(4).isApprox(0.25 * F0[2] + 0.75 * F0[3], 1e-14));
  EXPECT_EQ(t.F(2), t.F(4));  // a member reads its group's state
  EXPECT_EQ(t.tau(3), t.tau(4));
  EXPECT_EQ(t.F(1), F0[1]);  // a particle that stays itself keeps its own
  EXPECT_GT(t.tau(4).norm(), 0.0);
  // Once the run has begun, new merged points would start without their history. A point keeps
  // its G2P velocity from the last advance it went through (--velocity tracked); one that did not
  // go through it has none.
  EXPECT_EQ(t.last_velocity(0), nullptr);
  advance_to(t, stretch(1.005));
  ASSERT_NE(t.last_velocity(0), nullptr);
  EXPECT_EQ(*t.last_velocity(0), nsf::Vec3(0.5, 0, 0));
  EXPECT_EQ(t.last_velocity(1), nullptr);
  advance_to(t, stretch(1.005));
  EXPECT_NE(t.last_velocity(0), nullptr);
  table.X.push_back(nsf::Vec3::Zero());
  table.material.push_back(0);
  table.mat0.push_back(s.mat0[0]);
  table.merged_members.push_back({{1, 1.0}});
  nsf::testing::expect_contains(nsf::testing::error_of([&] { t.set_points(table); }),
                                "quadrature changed during the run");
  EXPECT_NO_THROW(t.check(1.0));
  nsf::testing::expect_contains(nsf::testing::error_of([&] { t.check(1e-4); }), "CFL bound");
}

// Stretched past yield and brought back by the same stretch, a von Mises point keeps a residual
// stress (its plastic flow); an elastic point returns to zero. h, a function of the latent, gives
// the same stress for the same shape either way.
TEST(TrackedParticles, APlasticPointRemembersItsPath) {
  for (const bool plastic : {true, false}) {
    Materials s =
        plastic ? one_material("von_mises", {{"E", kE}, {"nu", kNu}, {"yield_stress", 50.0}}, 1)
                : one_material("stvk_hencky", {{"E", kE}, {"nu", kNu}}, 1);
    nsf::TrackedParticles t({Mat3::Identity()}, s.mat0, s.material, s.materials, 1e-3);
    t.enlist("--stress tracked", true);
    EXPECT_LT(t.tau(0).norm(), 1e-9);
    advance_to(t, stretch(1.2));
    const Mat3 loaded = t.F(0);
    advance_to(t, loaded * stretch(1 / 1.2));
    if (plastic) {
      EXPECT_LT(loaded(0, 0), 1.2 - 1e-3) << "the return map should have taken some stretch away";
      EXPECT_GT(t.tau(0).norm(), 10.0) << "no residual stress after unloading";
    } else {
      EXPECT_NEAR(loaded(0, 0), 1.2, 1e-12);
      EXPECT_LT(t.tau(0).norm(), 1e-6);
    }
  }
}

// A step a guard redoes must start from the state before it: rollback to the newest mark puts
// back F, the plastic state, τ, C and each point's velocity however many advances ran since (a
// split step's substeps), and may be repeated; only the newest mark's state is kept, and without
// a mark there is nothing to roll back.
TEST(TrackedParticles, RollbackPutsBackTheStateOfTheNewestMark) {
  // Hardening: each plastic load raises the yield stress, which a rollback must take back.
  Materials s = one_material(
      "von_mises", {{"E", kE}, {"nu", kNu}, {"yield_stress", 50.0}, {"hardening", 10.0}}, 1);
  nsf::TrackedParticles t({Mat3::Identity()}, s.mat0, s.material, s.materials, 1e-3);
  t.enlist("--stress tracked", true);
  EXPECT_FALSE(t.rollback());
  advance_to(t, stretch(1.1));
  t.mark();
  advance_to(t, stretch(1.05));  // kept under the older mark only
  t.mark();
  const Mat3 F = t.F(0), tau = t.tau(0);
  const nsf::Vec3 v = *t.last_velocity(0);
  for (int attempt = 0; attempt < 2; ++attempt) {
    advance_to(t, t.F(0) * stretch(1.3));  // past the yield stress: the plastic state moves
    advance_to(t, t.F(0) * stretch(1.1));
    ASSERT_GT((t.F(0) - F).norm(), 0.1);
    ASSERT_TRUE(t.rollback());
    EXPECT_EQ(t.F(0), F);
    EXPECT_EQ(t.tau(0), tau);
    ASSERT_NE(t.last_velocity(0), nullptr);
    EXPECT_EQ(*t.last_velocity(0), v);
  }
  // The plastic state came back too: the same load from it gives the same F again.
  advance_to(t, t.F(0) * stretch(1.3));
  const Mat3 again = t.F(0);
  ASSERT_TRUE(t.rollback());
  advance_to(t, t.F(0) * stretch(1.3));
  EXPECT_EQ(t.F(0), again);
}

}  // namespace
