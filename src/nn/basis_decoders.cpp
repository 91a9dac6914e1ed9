// GCC 12 reports false -Wmaybe-uninitialized warnings from inside Eigen's AVX-512 kernels for
// dynamic-size products (in the intrinsics headers, not in this code).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include "nn/basis_decoders.h"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>

#include "core/dense_kernels.h"
#include "core/error.h"

namespace nsf {

Eigen::VectorXd CoefficientNet::operator()(const Eigen::VectorXd& x, Eigen::MatrixXd* J) const {
  // Column 0 is the layer's value a; with J, columns 1.. are ∂a/∂x, carried through the layers
  // (outputs × inputs). One product per layer gives both: W reads once (core/dense_kernels.h).
  // The layers fit together (checked when the model loads); the input must fit the first.
  const int64_t inputs = x.size();
  if (!W.empty() && inputs != this->inputs())
    fail("internal error: a coefficient network of ", this->inputs(), " inputs given ", inputs);
  const int cols = J ? int(1 + inputs) : 1;
  Eigen::MatrixXd A(inputs, cols), Y;
  A.col(0) = (x - in_shift).cwiseQuotient(in_scale);
  if (J) A.rightCols(inputs) = in_scale.cwiseInverse().asDiagonal();
  for (size_t i = 0; i < W.size(); ++i) {
    Y.resize(W[i].rows(), cols);
    narrow_product(W[i].data(), W[i].rows(), W[i].cols(), A.data(), cols, Y.data());
    Y.col(0) += b[i];
    if (i + 1 < W.size()) {  // ELU between layers, not after the last
      for (int64_t k = 0; k < Y.rows(); ++k) {
        if (Y(k, 0) > 0) continue;
        const double e = std::exp(Y(k, 0));
        Y(k, 0) = e - 1;
        if (J) Y.row(k).tail(inputs) *= e;
      }
    }
    A.swap(Y);
  }
  if (J) *J = out_scale.asDiagonal() * A.rightCols(inputs);
  return A.col(0).cwiseProduct(out_scale);
}

PointBasis PointBasis::rows(const std::vector<uint32_t>& ids) const {
  PointBasis out;
  out.dim = dim, out.K = K, out.points = ids.size();
  out.net = net, out.map = map;
  const size_t d = size_t(dim), dk = d * size_t(K);
  out.mean.resize(ids.size() * d), out.modes.resize(ids.size() * dk);
  for (size_t k = 0; k < ids.size(); ++k) {
    if (ids[k] >= points) fail("internal error: particle ", ids[k], " of a basis over ", points);
    std::copy_n(&mean[ids[k] * d], d, &out.mean[k * d]);
    std::copy_n(&modes[ids[k] * dk], dk, &out.modes[k * dk]);
  }
  return out;
}

void PointBasis::blend(const std::vector<std::pair<uint32_t, double>>& members,
                       std::vector<float>& mean_out, std::vector<float>& modes_out) const {
  const size_t d = size_t(dim), dk = size_t(dim) * size_t(K);
  std::vector<double> m(d, 0.0), b(dk, 0.0);
  for (const auto& [p, w] : members) {
    for (size_t i = 0; i < d; ++i) m[i] += w * mean[p * d + i];
    for (size_t i = 0; i < dk; ++i) b[i] += w * modes[p * dk + i];
  }
  mean_out.insert(mean_out.end(), m.begin(), m.end());
  modes_out.insert(modes_out.end(), b.begin(), b.end());
}

Eigen::VectorXf BasisDecoders::deformation_coefficients(const Eigen::VectorXd& z,
                                                        Eigen::MatrixXd* J) const {
  return u.coefficients(z, J).cast<float>();
}

namespace {

// (ẑ[, μ][, ż]): a field's coefficient input.
Eigen::VectorXd coefficient_input(const Eigen::VectorXd& z, bool with_mu, double mu,
                                  bool with_velocity, const Eigen::VectorXd* zdot,
                                  const char* field) {
  if (with_velocity && (!zdot || zdot->size() != z.size()))
    fail("internal error: ", field, "'s coefficients of this model need the latent velocity");
  const int64_t r = z.size();
  Eigen::VectorXd x(r + (with_mu ? 1 : 0) + (with_velocity ? r : 0));
  x.head(r) = z;
  if (with_mu) x[r] = mu;
  if (with_velocity) x.tail(r) = *zdot;
  return x;
}

}  // namespace

Eigen::VectorXd BasisDecoders::stress_input(const Eigen::VectorXd& z, double mu,
                                            const Eigen::VectorXd* zdot) const {
  return coefficient_input(z, stress_uses_mu, mu, stress_uses_velocity, zdot, "tau");
}

Eigen::VectorXf BasisDecoders::stress_coefficients(const Eigen::VectorXd& z, double mu,
                                                   const Eigen::VectorXd* zdot) const {
  return tau.coefficients(stress_input(z, mu, zdot)).cast<float>();
}

Eigen::VectorXd BasisDecoders::affine_input(const Eigen::VectorXd& z, double mu,
                                            const Eigen::VectorXd* zdot) const {
  // C's map reads μ with the velocity (the model files' layout since format version 5)
  return coefficient_input(z, affine_uses_velocity, mu, affine_uses_velocity, zdot, "C");
}

Eigen::VectorXf BasisDecoders::affine_coefficients(const Eigen::VectorXd& z, double mu,
                                                   const Eigen::VectorXd* zdot) const {
  return C.coefficients(affine_input(z, mu, zdot)).cast<float>();
}

Eigen::VectorXd BasisDecoders::latent_velocity(const Eigen::VectorXd& z, const float* v) const {
  Eigen::MatrixXd J;
  u.coefficients(z, &J);  // K × r
  Eigen::VectorXd cv = Eigen::VectorXd::Zero(u.K);
  for (size_t p = 0; p < u.points; ++p) {
    const float* B = &u.modes[p * 3 * size_t(u.K)];
    for (int d = 0; d < 3; ++d)
      for (int k = 0; k < u.K; ++k)
        cv[k] += double(B[size_t(d) * size_t(u.K) + size_t(k)]) * v[3 * p + size_t(d)];
  }
  return J.colPivHouseholderQr().solve(cv);
}

}  // namespace nsf
