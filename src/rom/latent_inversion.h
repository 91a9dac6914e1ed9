#pragma once
// Network inversion (§5.3, eq. 10): ẑ_{n+1} = argmin_ẑ Σ_{p∈S} ‖g(X_p, ẑ) − x_p^{n+1}‖², by
// Gauss–Newton warm-started from ẑ_n, with ∂g/∂ẑ from reverse-mode autodiff (3 backward
// passes over |S| points: each point's output depends only on its own copy of ẑ).
// Torch level: used by the stepper and its tests, not part of the public runtime header.
#include <torch/types.h>

#include <Eigen/Core>
#include <vector>

#include "core/types.h"
#include "rom/rom_options.h"

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

// g(X_p, ẑ) for the normalised rest positions Xn (|S| × 3, float) and ∂g/∂ẑ as a 3|S| × r
// matrix (row 3p + c is component c of particle p).
void deformation_jacobian(NeuralModel& model, const torch::Tensor& Xn, const Eigen::VectorXd& z,
                          Eigen::MatrixXd& J, std::vector<Vec3>& g);

InversionResult invert_deformation(NeuralModel& model, const torch::Tensor& Xn,
                                   const std::vector<Vec3>& target, const Eigen::VectorXd& z0,
                                   const GaussNewtonOptions& options);

// A whole frame's latent as the ROM's inversion would find it: Gauss–Newton from a start (the
// encoder's latent) on up to 1,024 particles spread evenly over P. Training fits h and l on these
// latents and `nsf eval --refine` measures them (docs/TRAINING.md, "latent mismatch").
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
  NeuralModel& model_;
  std::vector<size_t> ids_;
  torch::Tensor Xn_;
  GaussNewtonOptions options_;
};

}  // namespace nsf
