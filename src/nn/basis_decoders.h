#pragma once
// The per-point basis decoders at run time, without torch (docs/TRAINING.md, "Decoder families").
// Each field f ∈ {x − X, τ, C} of a basis model is
//     f_p(ẑ[, μ]) = mean_p + B_p · c_f(ẑ[, μ]),
// B_p the K_f modes of particle p (from the SVD of the training frames), c_f a small ELU network
// or a thin-plate-spline map (nn/rbf_map.h) of the latent, evaluated once per step. A field at a
// point costs dim·K_f multiply-adds in float; ∂g/∂ẑ at a point is B_p · ∂c/∂ẑ, with ∂c/∂ẑ (K × r)
// computed once.
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/dense_kernels.h"
#include "core/types.h"
#include "nn/rbf_map.h"

namespace nsf {

// A small ELU MLP in double: input (x − in_shift)/in_scale, hidden layers with ELU, output
// scaled by out_scale (each coefficient's training spread).
struct CoefficientNet {
  std::vector<Eigen::MatrixXd> W;  // layer i: out × in
  std::vector<Eigen::VectorXd> b;
  Eigen::VectorXd in_shift, in_scale, out_scale;

  // c(x); with J, also ∂c/∂x (outputs × inputs).
  Eigen::VectorXd operator()(const Eigen::VectorXd& x, Eigen::MatrixXd* J = nullptr) const;
  int64_t inputs() const { return W.empty() ? 0 : W.front().cols(); }
  int64_t outputs() const { return W.empty() ? 0 : W.back().rows(); }
};

// One field's basis over the particles: dim values per point, K modes.
struct PointBasis {
  int dim = 0, K = 0;
  size_t points = 0;
  std::vector<float> mean;   // points × dim
  std::vector<float> modes;  // points × dim × K, row-major per point
  CoefficientNet net;
  RbfMap map;  // when not empty, the coefficients are the map's, not the network's

  // c(x) from the map or the network, with ∂c/∂x when J is given.
  Eigen::VectorXd coefficients(const Eigen::VectorXd& x, Eigen::MatrixXd* J = nullptr) const {
    return map.empty() ? net(x, J) : map(x, J);
  }

  // out[0..dim) = mean_p + B_p c, for particle p.
  // One dot product of K per value: a dim × K product dispatched per point costs more than
  // its arithmetic.
  void value(size_t p, const Eigen::VectorXf& c, float* out) const {
    value_of(&mean[p * size_t(dim)], &modes[p * size_t(dim) * size_t(K)], c, out);
  }
  // The same for rows held elsewhere (a merged point's blend): mean m (dim), modes B (dim × K).
  // The ROM reads every row once per step, so this is a cloned kernel (core/dense_kernels.h)
  // called per point: a general product's set-up per point would cost more than its arithmetic.
  void value_of(const float* m, const float* B, const Eigen::VectorXf& c, float* out) const {
    rows_times_vectors(B, dim, K, c.data(), 1, out);
    for (int d = 0; d < dim; ++d) out[d] += m[d];
  }
  // The same field at the particles `ids` only, in that order (coefficients shared).
  PointBasis rows(const std::vector<uint32_t>& ids) const;
  // The mean and modes of a point standing for several particles, mass-weighted.
  void blend(const std::vector<std::pair<uint32_t, double>>& members, std::vector<float>& mean_out,
             std::vector<float>& modes_out) const;
  size_t bytes() const { return (mean.size() + modes.size()) * sizeof(float); }
};

// The three fields of a basis model and what their networks take.
struct BasisDecoders {
  PointBasis u, tau, C;    // x − X (3), τ (xx yy zz xy yz xz, 6), C (row-major 9)
  std::vector<Vec3> rest;  // X of every particle
  bool stress_uses_mu = false;
  // C's coefficients of (ẑ, μ, ż): the affine matrices are velocity gradients, which the latent
  // velocity ż carries and ẑ alone does not (docs/TRAINING.md, "Coefficient maps").
  bool affine_uses_velocity = false;
  // τ's coefficients of (ẑ[, μ], ż): where r leaves a vibration's phase out of ẑ, ż holds it.
  bool stress_uses_velocity = false;
  bool reads_velocity() const { return affine_uses_velocity || stress_uses_velocity; }

  // c_u(ẑ) (the encoder's raw latent, as g sees it) with ∂c_u/∂ẑ when J is given.
  Eigen::VectorXf deformation_coefficients(const Eigen::VectorXd& z,
                                           Eigen::MatrixXd* J = nullptr) const;
  // ż is read only when the field's coefficients use it (then it must be given: an internal
  // error if not).
  Eigen::VectorXf stress_coefficients(const Eigen::VectorXd& z, double mu,
                                      const Eigen::VectorXd* zdot = nullptr) const;
  Eigen::VectorXf affine_coefficients(const Eigen::VectorXd& z, double mu = 0,
                                      const Eigen::VectorXd* zdot = nullptr) const;
  // The latent velocity that best explains particle velocities v (|P| × 3) at ẑ: the least-squares
  // ż of B_u (∂c_u/∂ẑ) ż = v (B_u's modes are orthonormal over the particles).
  Eigen::VectorXd latent_velocity(const Eigen::VectorXd& z, const float* v) const;
  // The input of τ's coefficients: (ẑ[, μ][, ż]); of C's: (ẑ) or, with velocity, (ẑ, μ, ż).
  Eigen::VectorXd stress_input(const Eigen::VectorXd& z, double mu,
                               const Eigen::VectorXd* zdot) const;
  Eigen::VectorXd affine_input(const Eigen::VectorXd& z, double mu,
                               const Eigen::VectorXd* zdot) const;
  size_t bytes() const { return u.bytes() + tau.bytes() + C.bytes(); }
};

}  // namespace nsf
