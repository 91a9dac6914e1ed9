#pragma once
// The reduced-order step's inversion (§5.3, eq. 10): the Gauss–Newton fit of nn/latent_inversion.h,
// which training's latent refinement shares, with what the ROM adds to it: the latent prior of
// the model's training latents (latent_prior.h) at ε = RomOptions::latent_prior, the tighter fit
// of the initial state, and a fit that fails as RomDiverged (a search over settings rules the
// setting out; rom/step/rom_diverged.h).
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "core/types.h"
#include "nn/gauss_newton.h"
#include "nn/latent_inversion.h"
#include "nn/model_record.h"
#include "rom/inversion/latent_prior.h"

namespace nsf {

class RomInversion {
 public:
  // options: the step's fit (RomOptions::inversion); latent_prior: ε in metres, 0 for none.
  // free_dims: entries after the model's latent that the fit also solves for and the prior leaves
  // free (the rigid frames' θ and t, rom/step/rigid_frames.h).
  // Throws nsf::Error for an ε that is not a length, or for an ε > 0 with a model that stores no
  // training latents.
  RomInversion(const ModelRecord& model, const GaussNewtonOptions& options, double latent_prior,
               int free_dims = 0);

  // ẑ fitted to the samples' positions `target` from `start` as tightly as the initial state
  // needs (8 iterations, tolerance 1e-7), under the prior as the steps will be.
  Eigen::VectorXd fit_initial(SampleDeformation& g, const std::vector<Vec3>& target,
                              const Eigen::VectorXd& start) const;
  // The step's fit to `target`, warm-started from ẑ_n = `z` (on the caller's BLAS threads:
  // options().threads). A fit that fails or is not finite throws RomDiverged naming step n at
  // time t: the step before had already run away.
  InversionResult fit_step(SampleDeformation& g, const std::vector<Vec3>& target,
                           const Eigen::VectorXd& z, long n, double t) const;

  // The step's Gauss–Newton options, the prior included.
  const GaussNewtonOptions& options() const { return options_; }
  // ẑ's distance from the training runs' latents, in training spreads (ẑ: the model's part of the
  // latent); −1 for a model that does not store them.
  double training_distance(const Eigen::VectorXd& z) const;

 private:
  std::unique_ptr<LatentPrior> prior_;      // null where the model stores no training latents
  std::unique_ptr<LatentPenalty> penalty_;  // the prior, over the model's part of the latent
  GaussNewtonOptions options_;
};

}  // namespace nsf
