// The thinned quadrature of the ROM's MPM step (rom/quadrature.h): per grid cell of the rest
// shape and material, a few particles carry the whole cell's mass and volume.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include "rom/quadrature.h"

using nsf::Vec3;

namespace {

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
  std::tuple<int, int, int, int> bin(size_t p) const {
    return {int(X[p][0] / dx), int(X[p][1] / dx), int(X[p][2] / dx), material[p]};
  }
};

}  // namespace

TEST(RomQuadrature, EachCellKeepsItsMassAndVolumeOnTheKeptParticles) {
  const Block b;
  const std::vector<uint32_t> keep = {5, 77};  // e.g. sample particles: always kept
  for (int per_cell : {1, 3}) {
    const nsf::ThinnedQuadrature q =
        nsf::thin_quadrature(b.X, b.mass, b.vol0, b.material, b.lo, b.dx, per_cell, keep);
    std::map<std::tuple<int, int, int, int>, double> m_all, m_q, v_all, v_q;
    std::map<std::tuple<int, int, int, int>, int> count;
    for (size_t p = 0; p < b.X.size(); ++p)
      m_all[b.bin(p)] += b.mass[p], v_all[b.bin(p)] += b.vol0[p];
    for (uint32_t p : q.ids) {
      m_q[b.bin(p)] += q.mass[p], v_q[b.bin(p)] += q.vol0[p];
      ++count[b.bin(p)];
    }
    ASSERT_EQ(m_all.size(), 24u);
    for (const auto& [cell, m] : m_all) {
      EXPECT_NEAR(m_q[cell], m, 1e-12 * m) << "per cell " << per_cell;
      EXPECT_NEAR(v_q[cell], v_all[cell], 1e-18);
    }
    for (const auto& [cell, n] : count) {
      const bool has_keep = cell == b.bin(5) || cell == b.bin(77);
      EXPECT_EQ(n, has_keep && per_cell == 1 ? 1 : per_cell);
    }
    EXPECT_EQ(q.ids.size(), 24u * per_cell);
    for (uint32_t p : keep) EXPECT_GT(q.mass[p], 0) << "kept particle " << p;
    std::set<uint32_t> ids(q.ids.begin(), q.ids.end());
    for (size_t p = 0; p < b.X.size(); ++p) {
      if (!ids.count(uint32_t(p))) {
        EXPECT_EQ(q.mass[p], 0.0);
      }
    }
  }
}

TEST(RomQuadrature, PointsOfACellSpreadAndMaterialsAreNotMerged) {
  Block b;
  // Second material in the first cell: the same positions, another material id.
  const size_t n = b.X.size();
  for (size_t p = 0; p < n; ++p)
    if (b.bin(p) == std::make_tuple(0, 0, 0, 0)) {
      b.X.push_back(b.X[p]), b.mass.push_back(2.0), b.vol0.push_back(b.vol0[p]);
      b.material.push_back(1);
    }
  const nsf::ThinnedQuadrature q =
      nsf::thin_quadrature(b.X, b.mass, b.vol0, b.material, b.lo, b.dx, 2, {});
  EXPECT_EQ(q.ids.size(), 25u * 2);
  double m1 = 0;
  for (uint32_t p : q.ids)
    if (b.material[p] == 1) m1 += q.mass[p];
  EXPECT_NEAR(m1, 16.0, 1e-12);  // the 8 particles of material 1, 2 kg each
  // Two points per cell: the farthest-point rule takes opposite corners of the 2³ sub-lattice.
  for (size_t a = 0; a < q.ids.size(); ++a)
    for (size_t c = a + 1; c < q.ids.size(); ++c) {
      if (b.bin(q.ids[a]) == b.bin(q.ids[c])) {
        EXPECT_NEAR((b.X[q.ids[a]] - b.X[q.ids[c]]).norm(), std::sqrt(3.0) * 0.05, 1e-12);
      }
    }
}

TEST(RomQuadrature, ZeroPerCellKeepsEveryParticleAsItIs) {
  const Block b;
  const nsf::ThinnedQuadrature q =
      nsf::thin_quadrature(b.X, b.mass, b.vol0, b.material, b.lo, b.dx, 0, {});
  ASSERT_EQ(q.ids.size(), b.X.size());
  for (size_t p = 0; p < b.X.size(); ++p) {
    EXPECT_EQ(q.ids[p], p);
    EXPECT_EQ(q.mass[p], b.mass[p]);
    EXPECT_EQ(q.vol0[p], b.vol0[p]);
  }
}
