#pragma once
// Network inversion (§5.3, eq. 10): ẑ_{n+1} = argmin_ẑ Σ_{p∈S} ‖g(X_p, ẑ) − x_p^{n+1}‖², by
// Gauss–Newton warm-started from ẑ_n, with ∂g/∂ẑ from reverse-mode autodiff (3 backward
// passes over |S| points: each point's output depends only on its own copy of ẑ).
// Torch-free: the basis model's g (BasisSamples) and the fit; the networks' g is in
// nn/network_samples.h.
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "core/types.h"
#include "nn/basis_decoders.h"
#include "nn/gauss_newton.h"

namespace nsf {

struct InversionResult {
  Eigen::VectorXd z;
  int iterations = 0;
  double rms_residual =
      0;  // √(mean ‖g(X_p, ẑ) − x_p‖²) at the returned ẑ (Taylor: before the step)
  // g(X_p, ẑ) at the returned ẑ, as the last evaluation left it; empty after a Taylor step,
  // which never evaluates g at the latent it returns.
  std::vector<Vec3> fitted;
};

// g on a fixed set of sample points, as the fit needs it: the deformation sources of the
// reduced-order stepper (src/rom) hand one out for S.
class SampleDeformation {
 public:
  virtual ~SampleDeformation() = default;
  virtual size_t size() const = 0;
  virtual void evaluate(const Eigen::VectorXd& z, std::vector<Vec3>& g) = 0;
  // g and ∂g/∂ẑ as a 3|S| × r matrix (row 3p + c is component c of sample p).
  virtual void jacobian(const Eigen::VectorXd& z, Eigen::MatrixXd& J, std::vector<Vec3>& g) = 0;
};

// A basis model's g at particles: x_p = X_p + mean_p + B_p c_u(ẑ), ∂x_p/∂ẑ = B_p ∂c_u/∂ẑ.
class BasisSamples final : public SampleDeformation {
 public:
  BasisSamples(PointBasis u, std::vector<Vec3> rest);
  size_t size() const override { return rest_.size(); }
  void evaluate(const Eigen::VectorXd& z, std::vector<Vec3>& g) override;
  void jacobian(const Eigen::VectorXd& z, Eigen::MatrixXd& J, std::vector<Vec3>& g) override;

 private:
  // g = X + mean + B·c at the samples, B·c the first of each `stride` products.
  void positions(const float* products, int stride, std::vector<Vec3>& g) const;

  PointBasis u_;
  std::vector<Vec3> rest_;
};

InversionResult invert_deformation(SampleDeformation& g, const std::vector<Vec3>& target,
                                   const Eigen::VectorXd& z0, const GaussNewtonOptions& options);
}  // namespace nsf
