#include "core/body_motion.h"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "core/error.h"
#include "core/svd3.h"

namespace nsf {

BodyMotion fit_body_motion(const std::vector<Vec3>& X, const std::vector<Vec3>& x,
                           const std::vector<Vec3>& v, const std::vector<double>& mass,
                           const std::vector<uint32_t>& members) {
  if (members.empty()) fail("body motion: the body has no particles");
  if (x.size() != X.size() || mass.size() != X.size() || (!v.empty() && v.size() != X.size()))
    fail("body motion: ", X.size(), " rest positions, ", x.size(), " positions, ", v.size(),
         " velocities and ", mass.size(), " masses");
  BodyMotion b;
  Vec3 c0 = Vec3::Zero();
  for (uint32_t p : members) {
    if (p >= X.size()) fail("body motion: particle ", p, " of ", X.size());
    b.mass += mass[p];
    c0 += mass[p] * X[p];
    b.centre += mass[p] * x[p];
    if (!v.empty()) b.velocity += mass[p] * v[p];
  }
  if (!(b.mass > 0)) fail("body motion: the body has no mass");
  c0 /= b.mass, b.centre /= b.mass, b.velocity /= b.mass;
  b.rest_centre = c0;
  Mat3 H = Mat3::Zero(), I = Mat3::Zero();
  Vec3 L = Vec3::Zero();
  for (uint32_t p : members) {
    const Vec3 d = x[p] - b.centre;
    H += mass[p] * d * (X[p] - c0).transpose();
    I += mass[p] * (d.squaredNorm() * Mat3::Identity() - d * d.transpose());
    if (!v.empty()) L += mass[p] * d.cross(v[p] - b.velocity);
  }
  if (members.size() > 1 && H.cwiseAbs().maxCoeff() > 0) {
    Mat3 S;
    polar3(H, b.rotation, S);
    // I's pseudo-inverse: a body on a line turns freely about it, and no ω along it is measured.
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(I);
    const double floor = 1e-12 * eig.eigenvalues().maxCoeff();
    for (int k = 0; k < 3; ++k)
      if (eig.eigenvalues()[k] > floor) {
        const Vec3 e = eig.eigenvectors().col(k);
        b.angular_velocity += (e.dot(L) / eig.eigenvalues()[k]) * e;
      }
  }
  double misfit = 0;
  for (uint32_t p : members)
    misfit += mass[p] * (b.rotation * (X[p] - c0) + b.centre - x[p]).squaredNorm();
  b.rms_misfit = std::sqrt(misfit / b.mass);
  return b;
}

}  // namespace nsf
