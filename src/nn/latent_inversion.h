#pragma once
// Network inversion (§5.3, eq. 10): ẑ_{n+1} = argmin_ẑ Σ_{p∈S} ‖g(X_p, ẑ) − x_p^{n+1}‖², by
// Gauss–Newton warm-started from ẑ_n, with ∂g/∂ẑ from reverse-mode autodiff (3 backward
// passes over |S| points: each point's output depends only on its own copy of ẑ).
// Torch level: used by the reduced-order stepper (src/rom), by training's latent refinement and by
// their tests; not part of the public runtime header.
#include <torch/types.h>

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "core/types.h"
#include "nn/basis_decoders.h"
#include "nn/gauss_newton.h"

namespace nsf {

class NeuralModel;

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

// The network g at normalised rest positions Xn (|S| × 3, float).
class NetworkSamples final : public SampleDeformation {
 public:
  NetworkSamples(NeuralModel& model, torch::Tensor Xn);
  size_t size() const override;
  void evaluate(const Eigen::VectorXd& z, std::vector<Vec3>& g) override;
  void jacobian(const Eigen::VectorXd& z, Eigen::MatrixXd& J, std::vector<Vec3>& g) override;

 private:
  NeuralModel& model_;
  torch::Tensor Xn_;
};

// A basis model's g at particles: x_p = X_p + mean_p + B_p c_u(ẑ), ∂x_p/∂ẑ = B_p ∂c_u/∂ẑ.
class BasisSamples final : public SampleDeformation {
 public:
  BasisSamples(PointBasis u, std::vector<Vec3> rest);
  size_t size() const override { return rest_.size(); }
  void evaluate(const Eigen::VectorXd& z, std::vector<Vec3>& g) override;
  void jacobian(const Eigen::VectorXd& z, Eigen::MatrixXd& J, std::vector<Vec3>& g) override;

 private:
  PointBasis u_;
  std::vector<Vec3> rest_;
};

// g at the particles `ids` (rest positions X[ids]) of the model's scene, for either family.
std::unique_ptr<SampleDeformation> sample_deformation(NeuralModel& model,
                                                      const std::vector<Vec3>& X,
                                                      const std::vector<uint32_t>& ids);

// g(X_p, ẑ) for the normalised rest positions Xn (|S| × 3, float) and ∂g/∂ẑ as a 3|S| × r
// matrix (row 3p + c is component c of particle p).
void deformation_jacobian(NeuralModel& model, const torch::Tensor& Xn, const Eigen::VectorXd& z,
                          Eigen::MatrixXd& J, std::vector<Vec3>& g);

InversionResult invert_deformation(SampleDeformation& g, const std::vector<Vec3>& target,
                                   const Eigen::VectorXd& z0, const GaussNewtonOptions& options);
// The same for the network g at Xn.
InversionResult invert_deformation(NeuralModel& model, const torch::Tensor& Xn,
                                   const std::vector<Vec3>& target, const Eigen::VectorXd& z0,
                                   const GaussNewtonOptions& options);

// A whole frame's latent as the ROM's inversion would find it: Gauss–Newton from a start (the
// encoder's latent) on up to 1,024 particles spread evenly over P. Training fits h and l on these
// latents and `nsf eval --refine` measures them (docs/TRAINING.md, "Latents for h and l").
class FrameLatentRefiner {
 public:
  FrameLatentRefiner(NeuralModel& model, const std::vector<Vec3>& rest, int iterations);
  // x: the frame's positions, 3|P| floats (particle-major, as datasets store them).
  Eigen::VectorXd refine(const float* x, const Eigen::VectorXd& start) const;
  // Several frames, one per thread on as many threads as the GEMMs have, each thread's GEMMs on
  // one BLAS thread: a frame's GEMMs are too small to split, so whole frames in parallel finish
  // sooner (2 threads: 1.25-1.85× over frame by frame on 2 BLAS threads, bench/nn_throughput
  // refine_frames). z holds the starts on entry and the refined latents on return; the result
  // is the same as refine() frame by frame on one BLAS thread.
  void refine_many(const std::vector<const float*>& x, std::vector<Eigen::VectorXd>& z) const;

  static constexpr size_t kMaxParticles = 1024;

 private:
  std::vector<size_t> ids_;
  std::unique_ptr<SampleDeformation> g_;
  GaussNewtonOptions options_;
};

}  // namespace nsf
