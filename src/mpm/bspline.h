#pragma once
// Quadratic B-spline interpolation stencil: a particle talks to the 3x3x3 nodes starting at `base`.
#include <cmath>

#include "core/types.h"

namespace nsf {

struct Stencil {
  int base[3];     // lowest node index along each axis
  double fx[3];    // particle position relative to base, in cells, in [0.5, 1.5)
  double w[3][3];  // w[axis][offset] for offsets 0, 1, 2
};

inline Stencil quadratic_stencil(const Vec3& x, const Vec3& lo, double inv_dx) {
  Stencil s;
  for (int d = 0; d < 3; ++d) {
    double gx = (x[d] - lo[d]) * inv_dx;
    s.base[d] = static_cast<int>(std::floor(gx - 0.5));
    double f = gx - s.base[d];
    s.fx[d] = f;
    s.w[d][0] = 0.5 * (1.5 - f) * (1.5 - f);
    s.w[d][1] = 0.75 - (f - 1.0) * (f - 1.0);
    s.w[d][2] = 0.5 * (f - 0.5) * (f - 0.5);
  }
  return s;
}

// APIC/MLS inertia-like scaling D^-1 = 4/dx^2 for quadratic B-splines (§3.3: 12/(dx^2 (b+1))).
inline double apic_scale(double inv_dx) {
  return 4.0 * inv_dx * inv_dx;
}

}  // namespace nsf
