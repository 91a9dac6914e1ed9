#include "rom/quadrature.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>

#include "core/error.h"

namespace nsf {

namespace {

// Greedy farthest-point order within one bin, starting from the particle nearest its centroid,
// after the particles that must stay. Returns the kept members.
std::vector<uint32_t> spread_pick(const std::vector<Vec3>& X, const std::vector<uint32_t>& bin,
                                  const std::vector<uint8_t>& must, int per_cell) {
  std::vector<uint32_t> kept;
  for (uint32_t p : bin)
    if (must[p]) kept.push_back(p);
  if (int(kept.size()) >= per_cell) return kept;
  std::vector<double> gap(bin.size(), std::numeric_limits<double>::infinity());
  auto update_gaps = [&](uint32_t q) {
    for (size_t k = 0; k < bin.size(); ++k) gap[k] = std::min(gap[k], (X[bin[k]] - X[q]).norm());
  };
  for (uint32_t q : kept) update_gaps(q);
  if (kept.empty()) {
    Vec3 c = Vec3::Zero();
    for (uint32_t p : bin) c += X[p];
    c /= double(bin.size());
    size_t best = 0;
    for (size_t k = 1; k < bin.size(); ++k)
      if ((X[bin[k]] - c).norm() < (X[bin[best]] - c).norm()) best = k;
    kept.push_back(bin[best]);
    update_gaps(bin[best]);
  }
  while (int(kept.size()) < per_cell && kept.size() < bin.size()) {
    const size_t far = size_t(std::max_element(gap.begin(), gap.end()) - gap.begin());
    kept.push_back(bin[far]);
    update_gaps(bin[far]);
  }
  return kept;
}

}  // namespace

ThinnedQuadrature thin_quadrature(const std::vector<Vec3>& X, const std::vector<double>& mass,
                                  const std::vector<double>& vol0,
                                  const std::vector<uint16_t>& material, const Vec3& lo, double dx,
                                  int per_cell, const std::vector<uint32_t>& keep) {
  const size_t n = X.size();
  if (mass.size() != n || vol0.size() != n || material.size() != n)
    fail("quadrature: ", n, " positions but ", mass.size(), " masses, ", vol0.size(),
         " volumes and ", material.size(), " material ids");
  ThinnedQuadrature q;
  if (per_cell <= 0) {
    q.ids.resize(n);
    std::iota(q.ids.begin(), q.ids.end(), 0u);
    q.mass = mass, q.vol0 = vol0;
    return q;
  }
  if (!(dx > 0)) fail("quadrature: the cell size must be positive, got ", dx);
  std::vector<uint8_t> must(n, 0);
  for (uint32_t p : keep) {
    if (p >= n) fail("quadrature: particle ", p, " to keep is not among the ", n);
    must[p] = 1;
  }
  // Bins in first-seen order, so the result does not depend on hashing.
  std::unordered_map<uint64_t, uint32_t> bin_of_key;
  std::vector<std::vector<uint32_t>> bins;
  for (size_t p = 0; p < n; ++p) {
    uint64_t key = material[p];
    for (int d = 0; d < 3; ++d)
      key = key * 1000003u + uint64_t(int64_t(std::floor((X[p][d] - lo[d]) / dx)) + (1 << 20));
    auto [it, fresh] = bin_of_key.emplace(key, uint32_t(bins.size()));
    if (fresh) bins.emplace_back();
    bins[it->second].push_back(uint32_t(p));
  }
  q.mass.assign(n, 0.0), q.vol0.assign(n, 0.0);
  for (const auto& bin : bins) {
    const std::vector<uint32_t> kept = spread_pick(X, bin, must, per_cell);
    double m_all = 0, v_all = 0, m_kept = 0, v_kept = 0;
    for (uint32_t p : bin) m_all += mass[p], v_all += vol0[p];
    for (uint32_t p : kept) m_kept += mass[p], v_kept += vol0[p];
    for (uint32_t p : kept) {
      q.mass[p] = m_kept > 0 ? mass[p] * (m_all / m_kept) : 0.0;
      q.vol0[p] = v_kept > 0 ? vol0[p] * (v_all / v_kept) : 0.0;
      q.ids.push_back(p);
    }
  }
  std::sort(q.ids.begin(), q.ids.end());
  return q;
}

}  // namespace nsf
