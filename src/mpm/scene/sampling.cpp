#include "mpm/scene/sampling.h"

#include <algorithm>
#include <cmath>

namespace nsf {

std::vector<Vec3> sample_shape(const Shape& shape, const Lattice& L) {
  std::vector<Vec3> out;
  Aabb b = shape.bounds();
  if (b.empty()) return out;
  const double h = L.spacing();
  long first[3], last[3];
  for (int a = 0; a < 3; ++a) {
    // Point n sits at lo + (n + ½)h. One extra layer each side absorbs rounding in the bounds;
    // the inside test makes the final decision.
    long top = static_cast<long>(std::floor((L.hi[a] - L.lo[a]) / h - 0.5));
    double from = std::max((b.lo[a] - L.lo[a]) / h - 0.5, -1.0);
    double to = std::min((b.hi[a] - L.lo[a]) / h - 0.5, static_cast<double>(top) + 1.0);
    first[a] = std::max(0L, static_cast<long>(std::ceil(from)) - 1);
    last[a] = std::min(top, static_cast<long>(std::floor(to)) + 1);
    if (last[a] < first[a]) return out;
  }
  for (long i = first[0]; i <= last[0]; ++i)
    for (long j = first[1]; j <= last[1]; ++j)
      for (long k = first[2]; k <= last[2]; ++k) {
        Vec3 p = L.lo + Vec3(i + 0.5, j + 0.5, k + 0.5) * h;
        if (shape.contains(p)) out.push_back(p);
      }
  return out;
}

}  // namespace nsf
