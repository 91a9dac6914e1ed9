#include "io/position_check.h"

#include <cmath>

#include "core/error.h"

namespace nsf {

void check_run_positions(const std::vector<Vec3>& x, const std::string& path, size_t frame) {
  for (size_t p = 0; p < x.size(); ++p) {
    // Written so that NaN, which compares false with everything, fails too.
    const bool ok = std::abs(x[p].x()) <= kMaxRunCoordinate &&
                    std::abs(x[p].y()) <= kMaxRunCoordinate &&
                    std::abs(x[p].z()) <= kMaxRunCoordinate;
    if (ok) continue;
    const bool finite =
        std::isfinite(x[p].x()) && std::isfinite(x[p].y()) && std::isfinite(x[p].z());
    fail(path, ": frame ", frame, ", particle ", p, " has position (", x[p].x(), ", ", x[p].y(),
         ", ", x[p].z(), "), ",
         finite ? "more than 1e6 m from the origin" : "which is not a finite number",
         "; the run file is damaged or was not written by a stable simulation");
  }
}

}  // namespace nsf
