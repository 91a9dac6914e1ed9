#include "rom/inversion/rom_inversion.h"

#include <cmath>

#include "core/error.h"
#include "rom/step/rom_diverged.h"

namespace nsf {

namespace {

// A penalty on the first entries of a latent that carries `free` more after them.
class PenaltyOnHead final : public LatentPenalty {
 public:
  PenaltyOnHead(const LatentPenalty& inner, int free) : inner_(inner), free_(free) {}
  Terms terms(const Eigen::VectorXd& z) const override {
    const int64_t r = z.size() - free_;
    Terms t = inner_.terms(z.head(r));
    t.gradient.conservativeResize(z.size());
    t.gradient.tail(free_).setZero();
    t.hessian.conservativeResize(z.size(), z.size());
    t.hessian.rightCols(free_).setZero();
    t.hessian.bottomRows(free_).setZero();
    return t;
  }

 private:
  const LatentPenalty& inner_;
  int free_;
};

}  // namespace

RomInversion::RomInversion(const ModelRecord& model, const GaussNewtonOptions& options,
                           double latent_prior, int free_dims)
    : options_(options) {
  if (!(latent_prior >= 0 && std::isfinite(latent_prior)))
    fail("rom: the latent prior's length must be a number of metres, 0 or more, got ",
         latent_prior);
  prior_ = training_latent_prior(model);
  if (latent_prior > 0) {
    if (!prior_)
      fail(
          "rom: the latent prior (--latent-prior, rom.latent_prior) needs the training runs' "
          "latents, and this model file has none (it was trained before nsf stored them): "
          "retrain it with nsf train, or run without the prior (--latent-prior 0)");
    if (free_dims > 0) penalty_ = std::make_unique<PenaltyOnHead>(*prior_, free_dims);
    options_.penalty = penalty_ ? penalty_.get() : prior_.get();
    options_.penalty_length = latent_prior;
  }
}

Eigen::VectorXd RomInversion::fit_initial(SampleDeformation& g, const std::vector<Vec3>& target,
                                          const Eigen::VectorXd& start) const {
  GaussNewtonOptions fit{8, 1e-7, false};
  fit.penalty = options_.penalty;
  fit.penalty_length = options_.penalty_length;
  return invert_deformation(g, target, start, fit).z;
}

InversionResult RomInversion::fit_step(SampleDeformation& g, const std::vector<Vec3>& target,
                                       const Eigen::VectorXd& z, long n, double t) const {
  InversionResult res;
  try {
    res = invert_deformation(g, target, z, options_);
  } catch (const Error& e) {  // a non-finite fit: the step before had already run away
    fail_diverged("rom: at step ", n, " (t = ", t, " s) ", e.what());
  }
  if (!res.z.allFinite())
    fail_diverged("rom: the latent fitted at step ", n, " (t = ", t,
                  " s) is not finite: the latent dynamics diverged");
  return res;
}

double RomInversion::training_distance(const Eigen::VectorXd& z) const {
  return prior_ ? std::sqrt(prior_->distance2(z)) : -1.0;
}

}  // namespace nsf
