// The thinned quadrature of the ROM's MPM step (rom/step/quadrature.h): per grid cell of the rest
// shape and material, the particles are merged into a few points at their groups' centres of
// mass, carrying the groups' mass and volume; the particles to keep stay themselves.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "error_matchers.h"
#include "rom/step/quadrature.h"

using nsf::Vec3;

namespace {

using Bin = std::tuple<int, int, int, int>;

// A 4 × 3 × 2-cell block of 2³ particles per cell (dx = 0.1), masses varying by particle.
struct Block {
  std::vector<Vec3> X;
  std::vector<double> mass, vol0;
  std::vector<uint16_t> material;
  Vec3 lo = Vec3::Zero();
  double dx = 0.1;
  Block() {
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 6; ++j)
        for (int k = 0; k < 4; ++k) {
          X.emplace_back((i + 0.5) * 0.05, (j + 0.5) * 0.05, (k + 0.5) * 0.05);
          mass.push_back(1.0 + 0.01 * double(X.size() % 7));
          vol0.push_back(1.25e-4);
          material.push_back(0);
        }
  }
  Bin bin_of(const Vec3& x, int m) const {
    return {int(std::floor(x[0] / dx)), int(std::floor(x[1] / dx)), int(std::floor(x[2] / dx)), m};
  }
  // Rest position and material of quadrature point `id`.
  Vec3 point(const nsf::ThinnedQuadrature& q, uint32_t id) const {
    return id < X.size() ? X[id] : q.merged_X[id - X.size()];
  }
  int material_of(const nsf::ThinnedQuadrature& q, uint32_t id) const {
    return material[id < X.size() ? id : q.merged_group[id - X.size()]];
  }
};

}  // namespace

TEST(RomQuadrature, EachCellKeepsItsMassVolumeAndCentreOfMass) {
  const Block b;
  const std::vector<uint32_t> keep = {5, 77};  // e.g. sample particles: they stay themselves
  for (int per_cell : {1, 2, 3}) {
    const nsf::ThinnedQuadrature q =
        nsf::thin_quadrature(b.X, b.mass, b.vol0, b.material, b.lo, b.dx, per_cell, keep);
    ASSERT_EQ(q.particles, b.X.size());
    ASSERT_EQ(q.mass.size(), b.X.size() + q.merged_X.size());
    std::map<Bin, double> m_all, m_q, v_all, v_q;
    std::map<Bin, Vec3> mx_all, mx_q;
    std::map<Bin, int> points;
    for (size_t p = 0; p < b.X.size(); ++p) {
      const Bin c = b.bin_of(b.X[p], 0);
      m_all[c] += b.mass[p], v_all[c] += b.vol0[p];
      mx_all[c] = mx_all.count(c) ? Vec3(mx_all[c] + b.mass[p] * b.X[p]) : Vec3(b.mass[p] * b.X[p]);
    }
    for (uint32_t id : q.ids) {
      const Vec3 x = b.point(q, id);
      const Bin c = b.bin_of(x, b.material_of(q, id));
      m_q[c] += q.mass[id], v_q[c] += q.vol0[id], ++points[c];
      mx_q[c] = mx_q.count(c) ? Vec3(mx_q[c] + q.mass[id] * x) : Vec3(q.mass[id] * x);
    }
    ASSERT_EQ(m_all.size(), 24u);
    for (const auto& [c, m] : m_all) {
      EXPECT_NEAR(m_q[c], m, 1e-12 * m) << "per cell " << per_cell;
      EXPECT_NEAR(v_q[c], v_all[c], 1e-18);
      EXPECT_LT((mx_q[c] - mx_all[c]).norm(), 1e-12) << "first moment, per cell " << per_cell;
      const bool has_keep = c == b.bin_of(b.X[5], 0) || c == b.bin_of(b.X[77], 0);
      EXPECT_EQ(points[c], per_cell + (has_keep ? 1 : 0));
    }
    for (uint32_t p : keep) {
      EXPECT_EQ(q.mass[p], b.mass[p]) << "kept particle " << p;
      EXPECT_TRUE(std::binary_search(q.ids.begin(), q.ids.end(), p));
    }
    // Particles merged away carry nothing themselves.
    for (size_t p = 0; p < b.X.size(); ++p) {
      if (p != 5 && p != 77) {
        EXPECT_EQ(q.mass[p], 0.0);
      }
    }
    EXPECT_TRUE(std::is_sorted(q.ids.begin(), q.ids.end()));
  }
}

TEST(RomQuadrature, OnePointPerFullCellSitsAtItsCentreAndMaterialsAreNotMerged) {
  Block b;
  // A second material in the first cell: the same positions, another material id.
  const size_t n = b.X.size();
  for (size_t p = 0; p < n; ++p)
    if (b.bin_of(b.X[p], 0) == Bin(0, 0, 0, 0)) {
      b.X.push_back(b.X[p]), b.mass.push_back(2.0), b.vol0.push_back(b.vol0[p]);
      b.material.push_back(1);
    }
  const nsf::ThinnedQuadrature q =
      nsf::thin_quadrature(b.X, b.mass, b.vol0, b.material, b.lo, b.dx, 1, {});
  ASSERT_EQ(q.ids.size(), 25u);
  ASSERT_EQ(q.merged_X.size(), 25u);
  double m1 = 0;
  for (uint32_t id : q.ids) {
    if (b.material_of(q, id) == 1) m1 += q.mass[id];
    // The 2³ lattice's centre of mass lies near the cell centre (masses vary by 1 %).
    const Vec3 x = b.point(q, id);
    const Vec3 centre = (x / b.dx).array().floor().matrix() * b.dx + Vec3::Constant(0.5 * b.dx);
    EXPECT_LT((x - centre).norm(), 0.01 * b.dx);
  }
  EXPECT_NEAR(m1, 16.0, 1e-12);  // the 8 particles of material 1, 2 kg each
}

TEST(RomQuadrature, ZeroPerCellKeepsEveryParticleAsItIs) {
  const Block b;
  const nsf::ThinnedQuadrature q =
      nsf::thin_quadrature(b.X, b.mass, b.vol0, b.material, b.lo, b.dx, 0, {});
  EXPECT_FALSE(q.thinned());
  ASSERT_EQ(q.ids.size(), b.X.size());
  for (size_t p = 0; p < b.X.size(); ++p) {
    EXPECT_EQ(q.ids[p], p);
    EXPECT_EQ(q.mass[p], b.mass[p]);
    EXPECT_EQ(q.vol0[p], b.vol0[p]);
  }
}

TEST(RomQuadrature, BadInputIsAClearError) {
  const Block b;
  nsf::testing::expect_contains(
      nsf::testing::error_of(
          [&] { nsf::thin_quadrature(b.X, b.mass, b.vol0, b.material, b.lo, b.dx, 1, {100000}); }),
      "particle 100000 to keep");
  const std::vector<double> short_mass(b.mass.begin(), b.mass.end() - 1);
  nsf::testing::expect_contains(
      nsf::testing::error_of(
          [&] { nsf::thin_quadrature(b.X, short_mass, b.vol0, b.material, b.lo, b.dx, 1, {}); }),
      "masses");
}

// A merged point of weak and sound particles (a weak region's edge) is as stiff as its group on
// average by mass; a group of one material keeps it exactly, plastic state included.
TEST(RomQuadrature, AMergedPointTakesItsGroupsMassWeightedModuli) {
  const Block b;
  std::vector<nsf::MaterialPoint> mat(b.X.size());
  for (size_t p = 0; p < mat.size(); ++p) {
    mat[p].mu = 100, mat[p].lambda = 200, mat[p].yield_stress = 3, mat[p].hardening = 7;
    if (b.X[p].x() < 0.1) mat[p].mu *= 0.01, mat[p].lambda *= 0.01, mat[p].yield_stress *= 0.5;
  }
  const nsf::ThinnedQuadrature q =
      nsf::thin_quadrature(b.X, b.mass, b.vol0, b.material, b.lo, b.dx, 1, {});
  ASSERT_TRUE(q.thinned());
  for (size_t j = 0; j < q.merged_X.size(); ++j) {
    const auto& members = q.merged_members[j];
    double mu = 0, lambda = 0, yield = 0;
    for (const auto& [p, w] : members)
      mu += w * mat[p].mu, lambda += w * mat[p].lambda, yield += w * mat[p].yield_stress;
    const nsf::MaterialPoint m = nsf::merged_material(members, q.merged_group[j], mat);
    EXPECT_NEAR(m.mu, mu, 1e-12 * mu);
    EXPECT_NEAR(m.lambda, lambda, 1e-12 * lambda);
    EXPECT_NEAR(m.yield_stress, yield, 1e-12 * yield);
    EXPECT_EQ(m.hardening, 7);
  }
  // A cell half weak: members on both sides of x = 0.1 within one cell of dx = 0.1 do not
  // exist in this block (cells align with it), so mix one group by hand.
  const std::vector<std::pair<uint32_t, double>> mixed = {{0, 0.25},
                                                          {uint32_t(mat.size() - 1), 0.75}};
  ASSERT_LT(b.X[0].x(), 0.1);
  ASSERT_GE(b.X.back().x(), 0.1);
  const nsf::MaterialPoint m = nsf::merged_material(mixed, 0, mat);
  EXPECT_DOUBLE_EQ(m.mu, 0.25 * 1 + 0.75 * 100);
  EXPECT_DOUBLE_EQ(m.lambda, 0.25 * 2 + 0.75 * 200);
  EXPECT_DOUBLE_EQ(m.yield_stress, 0.25 * 1.5 + 0.75 * 3);
  // One material: the representative itself, to the bit.
  const std::vector<std::pair<uint32_t, double>> sound = {{uint32_t(mat.size() - 1), 0.3},
                                                          {uint32_t(mat.size() - 2), 0.7}};
  const nsf::MaterialPoint s = nsf::merged_material(sound, uint32_t(mat.size() - 1), mat);
  EXPECT_EQ(s.mu, 100);
  EXPECT_EQ(s.lambda, 200);
}
