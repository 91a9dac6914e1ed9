#include "nn/held_out_points.h"

#include <cmath>

#include "core/error.h"
#include "nn/basis_decoders.h"

namespace nsf {

HeldOutPoints::HeldOutPoints(const NeuralFields& nf, size_t stride, const std::string& scheme,
                             int neighbours) {
  const BasisDecoders* bases = nf.bases();
  if (!bases)
    fail(
        "--held-out-particles measures how a basis model's fields read between particles; an "
        "MLP model's fields are functions of X everywhere (nsf train --decoder basis)");
  if (stride < 2) fail("--held-out-particles K needs K >= 2 (every K-th particle is held out)");
  X_ = bases->rest;
  std::vector<Vec3> held_X, others_X;
  for (size_t p = 0; p < X_.size(); ++p) {
    if (p % stride == stride / 2) {
      held_.push_back(p), held_X.push_back(X_[p]);
    } else {
      others_.push_back(p), others_X.push_back(X_[p]);
    }
  }
  weights_ = interpolate_points(others_X, held_X, scheme, neighbours);
}

void HeldOutPoints::start() {
  ex_ = nx_ = own_ex_ = 0;
  stress_ = affine_ = own_stress_ = own_affine_ = ErrorSum();
}

void HeldOutPoints::add_frame(const std::vector<Vec3>& xm, const std::vector<Mat3>& tm,
                              const std::vector<Mat3>& cm, const std::vector<Vec3>& x,
                              const float* tau, const float* C) {
  for (size_t i = 0; i < held_.size(); ++i) {
    // The displacement x − X is what varies smoothly between particles: read it, then add X.
    Vec3 u = Vec3::Zero();
    Mat3 t = Mat3::Zero(), c = Mat3::Zero();
    for (uint32_t e = weights_.start[i]; e < weights_.start[i + 1]; ++e) {
      const size_t q = others_[weights_.particle[e]];
      const double w = weights_.weight[e];
      u += w * (xm[q] - X_[q]), t += w * tm[q], c += w * cm[q];
    }
    const size_t p = held_[i];
    ex_ += (X_[p] + u - x[p]).squaredNorm(), own_ex_ += (xm[p] - x[p]).squaredNorm();
    nx_ += x[p].squaredNorm();
    const Mat3 t_true = stored_stress(&tau[6 * p]), c_true = stored_affine(&C[9 * p]);
    stress_.add(t, t_true), own_stress_.add(tm[p], t_true);
    affine_.add(c, c_true), own_affine_.add(cm[p], c_true);
  }
}

HeldOutErrors HeldOutPoints::errors() const {
  HeldOutErrors e;
  e.particles = held_.size();
  e.delta = nx_ > 0 ? std::sqrt(ex_ / nx_) : NAN;
  e.own_delta = nx_ > 0 ? std::sqrt(own_ex_ / nx_) : NAN;
  e.stress = stress_.relative(), e.own_stress = own_stress_.relative();
  e.affine = affine_.relative(), e.own_affine = own_affine_.relative();
  return e;
}

}  // namespace nsf
