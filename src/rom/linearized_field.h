#pragma once
// The ROM's "tangent cache" lever (docs/experiments/2026-11-22-tangent-cache.md): one decoder (g, h
// or l) replaced, per particle, by its first-order expansion in ẑ about an anchor latent ẑa,
//     f(X_p, ẑ) ≈ f(X_p, ẑa) + ∂f/∂ẑ(X_p, ẑa) (ẑ − ẑa),
// so that a step costs an r-term product per particle instead of a network evaluation. ẑ moves
// slowly, so the expansions are recomputed only when ẑ leaves a ball around the anchor; the
// Jacobians come from one batched call at ẑa and ẑa + ε e_i (r + 1 evaluations per particle).
// Torch level: used by the stepper and its tests.
#include <torch/types.h>

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <vector>

namespace nsf {

class LinearizedField {
 public:
  // (normalised rest positions m × 3, latents m × r) → outputs m × out_dim, as the model's
  // deform / stress / affine calls give them.
  using Network = std::function<torch::Tensor(const torch::Tensor& Xn, const torch::Tensor& z)>;

  // Xn_all: every particle's normalised rest position (|P| × 3). z_scale: each latent
  // component's training spread; `radius` (> 0) and the difference step are in those units.
  LinearizedField(Network net, int64_t out_dim, torch::Tensor Xn_all, Eigen::VectorXd z_scale,
                  double radius);

  // Makes every particle in `ids` expanded about one anchor. Re-anchors at z (and drops all
  // expansions) first when max_i |z_i − ẑa_i| / scale_i exceeds the radius, or when none exists.
  void prepare(const std::vector<uint32_t>& ids, const Eigen::VectorXd& z);

  // out[k · out_dim + c]: component c at particle ids[k]; every id must be prepared.
  void evaluate(const std::vector<uint32_t>& ids, const Eigen::VectorXd& z,
                std::vector<double>& out) const;

  long anchors() const { return anchors_; }        // re-anchorings so far
  long expansions() const { return expansions_; }  // particle expansions computed so far
  const Eigen::VectorXd& anchor() const { return anchor_; }

  static constexpr double kDifferenceStep = 1e-2;  // ε, in units of the latent's spread

 private:
  void expand(const std::vector<uint32_t>& ids);

  Network net_;
  int64_t d_;
  torch::Tensor Xn_all_;
  Eigen::VectorXd scale_, anchor_;
  double radius_;
  std::vector<int32_t> slot_;    // particle → row block in coeffs_, −1 when not expanded
  std::vector<uint32_t> owner_;  // slot → particle
  std::vector<double> coeffs_;   // per slot: d values, then d × r Jacobian (row-major)
  long anchors_ = 0, expansions_ = 0;
};

}  // namespace nsf
