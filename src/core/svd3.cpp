#include "core/svd3.h"

#include <limits>

namespace nsf::svd3_detail {

void svd3_rescaled(const Mat3& F, double max_abs, Mat3& U, Vec3& sigma, Mat3& V) {
  if (!std::isfinite(max_abs)) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    U.setConstant(nan);
    V.setConstant(nan);
    sigma.setConstant(nan);
    return;
  }
  if (max_abs == 0.0) {
    U.setIdentity();
    V.setIdentity();
    sigma.setZero();
    return;
  }
  // Scaling by a power of two is exact, so the decomposition of the scaled matrix is exactly
  // that of F up to the same factor on Σ.
  const int e = std::ilogb(max_abs);
  // scalbn rather than multiplying by 2^-e: for denormal F, 2^-e itself would overflow.
  const Mat3 scaled = F.unaryExpr([e](double x) { return std::scalbn(x, -e); });
  svd3_core(scaled, U, sigma, V);
  sigma = sigma.unaryExpr([e](double x) { return std::scalbn(x, e); });
}

Vec3 unit_orthogonal(const Vec3& u) {
  // Crossing with the axis least aligned with u keeps the result well away from zero length.
  int k = 0;
  if (std::abs(u[1]) < std::abs(u[k])) k = 1;
  if (std::abs(u[2]) < std::abs(u[k])) k = 2;
  return u.cross(Vec3::Unit(k)).normalized();
}

}  // namespace nsf::svd3_detail
