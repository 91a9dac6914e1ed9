#include "rom/step/quadrature.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>

#include "core/error.h"

namespace nsf {

namespace {

// Splits `members` into at most `groups` groups: seeds in farthest-point order from the member
// nearest the centroid, each member to its nearest seed (the first on ties). Returns a group index
// per member.
std::vector<int> group_members(const std::vector<Vec3>& X, const std::vector<uint32_t>& members,
                               int groups) {
  Vec3 c = Vec3::Zero();
  for (uint32_t p : members) c += X[p];
  c /= double(members.size());
  size_t first = 0;
  for (size_t k = 1; k < members.size(); ++k)
    if ((X[members[k]] - c).norm() < (X[members[first]] - c).norm()) first = k;
  std::vector<size_t> seeds = {first};
  std::vector<double> gap(members.size(), std::numeric_limits<double>::infinity());
  while (true) {
    for (size_t k = 0; k < members.size(); ++k)
      gap[k] = std::min(gap[k], (X[members[k]] - X[members[seeds.back()]]).norm());
    if (int(seeds.size()) >= groups || seeds.size() >= members.size()) break;
    seeds.push_back(size_t(std::max_element(gap.begin(), gap.end()) - gap.begin()));
  }
  std::vector<int> group(members.size(), 0);
  for (size_t k = 0; k < members.size(); ++k) {
    double best = std::numeric_limits<double>::infinity();
    for (size_t s = 0; s < seeds.size(); ++s) {
      const double d = (X[members[k]] - X[members[seeds[s]]]).norm();
      if (d < best) best = d, group[k] = int(s);
    }
  }
  return group;
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
  q.particles = n;
  if (per_cell <= 0) {
    q.ids.resize(n);
    std::iota(q.ids.begin(), q.ids.end(), 0u);
    q.mass = mass, q.vol0 = vol0;
    return q;
  }
  if (!(dx > 0)) fail("quadrature: the cell size must be positive, got ", dx);
  std::vector<uint8_t> kept(n, 0);
  for (uint32_t p : keep) {
    if (p >= n) fail("quadrature: particle ", p, " to keep is not among the ", n);
    kept[p] = 1;
  }
  // Bins in first-seen order, so the numbering does not depend on hashing.
  std::unordered_map<uint64_t, uint32_t> bin_of_key;
  std::vector<std::vector<uint32_t>> bins;
  for (size_t p = 0; p < n; ++p) {
    if (kept[p]) continue;
    uint64_t key = material[p];
    for (int d = 0; d < 3; ++d)
      key = key * 1000003u + uint64_t(int64_t(std::floor((X[p][d] - lo[d]) / dx)) + (1 << 20));
    auto [it, fresh] = bin_of_key.emplace(key, uint32_t(bins.size()));
    if (fresh) bins.emplace_back();
    bins[it->second].push_back(uint32_t(p));
  }
  q.mass.assign(n, 0.0), q.vol0.assign(n, 0.0);
  for (size_t p = 0; p < n; ++p)
    if (kept[p]) q.ids.push_back(uint32_t(p)), q.mass[p] = mass[p], q.vol0[p] = vol0[p];
  for (const auto& bin : bins) {
    const std::vector<int> group = group_members(X, bin, per_cell);
    const int groups = *std::max_element(group.begin(), group.end()) + 1;
    std::vector<double> m(groups, 0.0), v(groups, 0.0);
    std::vector<Vec3> mx(groups, Vec3::Zero());
    std::vector<uint32_t> member(groups, 0);
    std::vector<std::vector<std::pair<uint32_t, double>>> members(groups);
    for (size_t k = 0; k < bin.size(); ++k) {
      const int g = group[k];
      const uint32_t p = bin[k];
      m[g] += mass[p], v[g] += vol0[p], mx[g] += mass[p] * X[p], member[g] = p;
      members[g].emplace_back(p, mass[p]);
    }
    for (int g = 0; g < groups; ++g) {
      for (auto& [p, share] : members[g])
        share = m[g] > 0 ? share / m[g] : 1.0 / double(members[g].size());
      q.merged_members.push_back(std::move(members[g]));
      q.ids.push_back(uint32_t(n + q.merged_X.size()));
      q.merged_X.push_back(m[g] > 0 ? Vec3(mx[g] / m[g]) : X[member[g]]);
      q.merged_group.push_back(member[g]);
      q.mass.push_back(m[g]);
      q.vol0.push_back(v[g]);
    }
  }
  return q;
}

MaterialPoint merged_material(const std::vector<std::pair<uint32_t, double>>& members,
                              uint32_t representative, const std::vector<MaterialPoint>& mat) {
  MaterialPoint mp = mat.at(representative);
  const auto same = [&](const std::pair<uint32_t, double>& m) {
    const MaterialPoint& q = mat.at(m.first);
    return q.mu == mp.mu && q.lambda == mp.lambda && q.yield_stress == mp.yield_stress;
  };
  if (std::all_of(members.begin(), members.end(), same)) return mp;
  mp.mu = mp.lambda = mp.yield_stress = 0;
  for (const auto& [p, w] : members) {
    mp.mu += w * mat[p].mu;
    mp.lambda += w * mat[p].lambda;
    mp.yield_stress += w * mat[p].yield_stress;
  }
  return mp;
}

}  // namespace nsf
