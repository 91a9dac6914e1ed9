#pragma once
// The paper's network g on sample points for the inversion (nn/latent_inversion.h), with ∂g/∂ẑ
// from reverse-mode autodiff (3 backward passes over |S| points: each point's output depends only
// on its own copy of ẑ), and the frame latents training refines. Torch level (libnsf_nn).
#include <torch/types.h>

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "core/types.h"
#include "nn/latent_inversion.h"

namespace nsf {

class NeuralFields;
class NeuralModel;

// F = ∂g/∂X (physical rest coordinates) at the normalised rest positions Xn (m × 3, float) and
// per-particle latents zN (m × r, float), by reverse-mode autodiff: m × 3 × 3, row-major, double.
// CROM's stress reads it (F through the material).
torch::Tensor deformation_gradients(NeuralModel& model, const torch::Tensor& Xn,
                                    const torch::Tensor& zN);

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

// g at the particles `ids` (rest positions X[ids]) of the model's scene, for either family.
std::unique_ptr<SampleDeformation> sample_deformation(NeuralModel& model,
                                                      const std::vector<Vec3>& X,
                                                      const std::vector<uint32_t>& ids);

// g(X_p, ẑ) for the normalised rest positions Xn (|S| × 3, float) and ∂g/∂ẑ as a 3|S| × r
// matrix (row 3p + c is component c of particle p).
void deformation_jacobian(NeuralModel& model, const torch::Tensor& Xn, const Eigen::VectorXd& z,
                          Eigen::MatrixXd& J, std::vector<Vec3>& g);

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
  // The same for the model behind `fields`, loaded with LibTorch (NeuralFields::load): what the
  // ROM's error budget (rom/eval/error_budget.h) and `nsf eval --refine` measure.
  FrameLatentRefiner(NeuralFields& fields, const std::vector<Vec3>& rest, int iterations);
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
