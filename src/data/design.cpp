#include "data/design.h"

#include <algorithm>
#include <array>
#include <numeric>

#include "core/error.h"

namespace nsf {

double unit_draw(std::mt19937_64& rng) {
  return double(rng() >> 11) * 0x1.0p-53;
}

std::vector<double> latin_hypercube(int n, int d, uint64_t seed) {
  if (n < 1 || d < 1) fail("latin hypercube: needs n ≥ 1 points and d ≥ 1 axes, got ", n, ", ", d);
  std::mt19937_64 rng(seed);
  std::vector<double> out(size_t(n) * size_t(d));
  std::vector<int> strata(static_cast<size_t>(n));
  for (int k = 0; k < d; ++k) {
    std::iota(strata.begin(), strata.end(), 0);
    // Fisher–Yates on the raw draws (std::shuffle's use of the generator is not fixed).
    for (int i = n - 1; i > 0; --i)
      std::swap(strata[size_t(i)], strata[size_t(unit_draw(rng) * (i + 1))]);
    for (int i = 0; i < n; ++i)
      out[size_t(i) * size_t(d) + size_t(k)] = (strata[size_t(i)] + unit_draw(rng)) / n;
  }
  return out;
}

namespace {

// Joe & Kuo (2008), new-joe-kuo-6.21201: for axes 2 … 10 the degree s of the primitive
// polynomial, its coefficients a and the initial direction numbers m₁ … m_s. Axis 1 is the van der
// Corput sequence in base 2.
struct SobolAxis {
  int s;
  unsigned a;
  std::array<unsigned, 5> m;
};
constexpr std::array<SobolAxis, kSobolMaxDimensions - 1> kJoeKuo = {{
    {1, 0, {1}},
    {2, 1, {1, 3}},
    {3, 1, {1, 3, 1}},
    {3, 2, {1, 1, 1}},
    {4, 1, {1, 1, 3, 3}},
    {4, 4, {1, 3, 5, 13}},
    {5, 2, {1, 1, 5, 5, 17}},
    {5, 4, {1, 1, 5, 5, 5}},
    {5, 7, {1, 1, 7, 11, 19}},
}};
constexpr int kBits = 32;

std::array<uint32_t, kBits> directions(int axis) {
  std::array<uint32_t, kBits> v{};
  if (axis == 0) {
    for (int i = 0; i < kBits; ++i) v[size_t(i)] = uint32_t(1) << (kBits - 1 - i);
    return v;
  }
  const SobolAxis& p = kJoeKuo[size_t(axis - 1)];
  for (int i = 0; i < p.s; ++i) v[size_t(i)] = p.m[size_t(i)] << (kBits - 1 - i);
  for (int i = p.s; i < kBits; ++i) {
    uint32_t x = v[size_t(i - p.s)] ^ (v[size_t(i - p.s)] >> p.s);
    for (int k = 1; k < p.s; ++k)
      if ((p.a >> (p.s - 1 - k)) & 1u) x ^= v[size_t(i - k)];
    v[size_t(i)] = x;
  }
  return v;
}

}  // namespace

std::vector<double> sobol_points(int first, int n, int d, uint64_t seed) {
  if (d < 1 || d > kSobolMaxDimensions)
    fail("sobol: between 1 and ", kSobolMaxDimensions, " axes, got ", d);
  if (first < 0 || n < 0 || int64_t(first) + n > (int64_t(1) << 30))
    fail("sobol: points ", first, " … ", int64_t(first) + n - 1, " lie outside 0 … 2^30");
  std::mt19937_64 rng(seed);
  std::vector<uint32_t> shift(static_cast<size_t>(d));
  for (uint32_t& s : shift) s = uint32_t(rng() >> 32);
  std::vector<std::array<uint32_t, kBits>> v;
  for (int k = 0; k < d; ++k) v.push_back(directions(k));
  std::vector<double> out;
  out.reserve(size_t(n) * size_t(d));
  for (int i = first; i < first + n; ++i) {
    // Point i directly: the XOR of the direction numbers of i's Gray code's set bits.
    const uint32_t gray = uint32_t(i) ^ (uint32_t(i) >> 1);
    for (int k = 0; k < d; ++k) {
      uint32_t x = 0;
      for (int b = 0; b < kBits; ++b)
        if ((gray >> b) & 1u) x ^= v[size_t(k)][size_t(b)];
      out.push_back(double(x ^ shift[size_t(k)]) * 0x1.0p-32);
    }
  }
  return out;
}

}  // namespace nsf
