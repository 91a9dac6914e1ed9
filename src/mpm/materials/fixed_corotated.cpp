#include "mpm/materials/fixed_corotated.h"

#include <Eigen/SVD>

#include "mpm/materials/param_check.h"

namespace nsf {

MaterialPoint FixedCorotated::make_point(const ParamMap& params, const std::string& path) const {
  ParamReader r(params, path, parameter_names());
  double E = r.get("E", positive_range());
  double nu = r.get("nu", poisson_range());
  MaterialPoint mp;
  mp.mu = shear_modulus(E, nu);
  mp.lambda = lame_lambda(E, nu);
  return mp;
}

Mat3 FixedCorotated::update(Mat3& F, MaterialPoint& mp, double /*dt*/) const {
  // TEMPORARY: generic SVD; replaced by the fast robust svd3 in core/.
  Eigen::JacobiSVD<Mat3> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 U = svd.matrixU(), V = svd.matrixV();
  if (U.determinant() < 0) U.col(2) *= -1;
  if (V.determinant() < 0) V.col(2) *= -1;
  Mat3 R = U * V.transpose();
  double J = F.determinant();
  return 2.0 * mp.mu * (F - R) * F.transpose() + mp.lambda * (J - 1.0) * J * Mat3::Identity();
}

}  // namespace nsf
