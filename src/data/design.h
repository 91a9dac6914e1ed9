#pragma once
// Space-filling designs on the unit cube, for sweeps that vary several things at once (issue #55
// item 4; docs/SCENES.md, "Sweeps"). Both are seeded and use only std::mt19937_64's raw output,
// whose sequence the standard fixes, so a seed gives the same points with every library.
//   Latin hypercube: n points; along each axis every interval [k/n, (k+1)/n) holds exactly one.
//   Sobol: the first n points of the Sobol sequence (Joe & Kuo's direction numbers, up to
//     kSobolMaxDimensions axes) after its origin, shifted by a seeded digital shift (an XOR of
//     every coordinate's bits), which keeps the sequence's stratification.
#include <cstdint>
#include <random>
#include <vector>

namespace nsf {

// A uniform number in [0, 1) from the generator's raw output.
double unit_draw(std::mt19937_64& rng);

// n points × d coordinates in [0, 1), row-major (point i's coordinate k at [i·d + k]).
std::vector<double> latin_hypercube(int n, int d, uint64_t seed);

inline constexpr int kSobolMaxDimensions = 10;
// Points first … first + n − 1 of the shifted sequence (first ≥ 1 skips the origin); d ≤
// kSobolMaxDimensions. Later points fill the gaps of earlier ones, so a sweep's test runs are
// the points after its training runs.
std::vector<double> sobol_points(int first, int n, int d, uint64_t seed);

}  // namespace nsf
