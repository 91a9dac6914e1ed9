#pragma once
// The region of latent space the training runs visited, as a prior for the ROM's inversion
// (`nsf rom --latent-prior ε`, docs/ROM.md "Latent prior"). Each training run traces a curve
// ẑ(t) through latent space; the runs, in order of μ, span a surface over (μ, t), here the
// triangulated grid of their frames. The inversion may drift along latent directions that hardly
// move the sample particles but move h and l a lot
// (docs/experiments/2026-11-25-delta-floor-and-stress.md); the distance to this surface, in units
// of each component's training spread, penalises that: it is the Gauss–Newton fit's LatentPenalty
// (nn/gauss_newton.h). Torch-free: built from the latents the model's run-time record stores.
#include <Eigen/Core>
#include <atomic>
#include <memory>
#include <vector>

#include "nn/gauss_newton.h"
#include "nn/model_record.h"

namespace nsf {

class LatentPrior final : public LatentPenalty {
 public:
  // runs[j][i]: the latent of frame i of the run with the j-th smallest μ. Runs of unequal
  // length are cut to the shortest (a sweep's runs all have the scene's frame count). spread:
  // each latent component's training spread, the unit of distance (the model's norm_z).
  LatentPrior(const std::vector<std::vector<Eigen::VectorXd>>& runs, const Eigen::VectorXd& spread);

  // distance2: the squared distance to the surface, in training spreads; gradient: its half
  // derivative; hessian: half the second derivative of the distance to the plane of the closest
  // feature (Gauss–Newton's).
  using Nearest = LatentPenalty::Terms;
  Nearest nearest(const Eigen::VectorXd& z) const;
  double distance2(const Eigen::VectorXd& z) const;
  Terms terms(const Eigen::VectorXd& z) const override { return nearest(z); }

 private:
  // One triangle of the surface in whitened coordinates: corners a, b, c, edges e1 = b − a and
  // e2 = c − a with their Gram matrix and its sides a → b, b → c, c → a, all precomputed because
  // nearest() runs at every Gauss–Newton iteration; a ball holding each (centers_, radii_) lets
  // it skip the triangles that cannot be the closest.
  struct Triangle {
    int a, b, c;
    Eigen::VectorXd e1, e2, side[3];
    double a11, a12, a22, det;
  };
  Eigen::VectorXd whiten(const Eigen::VectorXd& z) const;
  // The closest point to w on the surface, and an orthonormal basis of the plane of the feature
  // it lies on (two columns in a triangle's interior, one on an edge, none at a corner).
  double closest(const Eigen::VectorXd& w, Eigen::VectorXd* point, Eigen::MatrixXd* plane) const;

  std::vector<Eigen::VectorXd> w_;  // whitened training latents
  std::vector<Triangle> tri_;
  Eigen::MatrixXd centers_;  // r × triangles: each triangle's centroid
  Eigen::ArrayXd radii_;     // and the distance from it to the farthest corner
  // The triangle closest to the previous query: the inversion's latent moves little between
  // calls, so its corners bound the next distance tightly. Only a hint (any value gives the same
  // answer), atomic so that threads sharing a prior do not race.
  mutable std::atomic<size_t> hint_{0};
  Eigen::VectorXd spread_;
};

// The prior of a model's training runs (its record's latents, runs in order of μ, and their
// spreads), or null where the model stores no training latents (a file older than that).
std::unique_ptr<LatentPrior> training_latent_prior(const ModelRecord& model);

}  // namespace nsf
