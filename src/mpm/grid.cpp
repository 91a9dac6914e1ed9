#include "mpm/grid.h"

#include <cmath>

#include "core/error.h"

namespace nsf {

Grid::Grid(const Vec3& lo, const Vec3& hi, double dx) : lo_(lo), dx_(dx), inv_dx_(1.0 / dx) {
  for (int d = 0; d < 3; ++d) {
    double cells = (hi[d] - lo[d]) / dx;
    if (!(cells >= 4)) fail("grid: the domain must span at least 4 cells of dx along each axis");
    n_[d] = static_cast<int>(std::ceil(cells - 1e-9)) + 1;
  }
  double count = double(n_[0]) * n_[1] * n_[2];
  if (count > 2e9) fail("grid: ", n_[0], "x", n_[1], "x", n_[2], " nodes is too many; raise dx");
  nodes_.resize(static_cast<size_t>(count));
}

}  // namespace nsf
