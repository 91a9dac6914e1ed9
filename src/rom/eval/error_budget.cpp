#include "rom/eval/error_budget.h"

#include <cmath>

#include "nn/basis_decoders.h"
#include "nn/config.h"
#include "nn/network_samples.h"

namespace nsf {

FieldErrors ErrorBudget::Sums::errors() const {
  FieldErrors e;
  if (x.ref > 0) e.delta = x.relative();
  if (stress.ref > 0) e.stress = stress.relative();
  if (affine.ref > 0) e.affine = affine.relative();
  return e;
}

ErrorBudget::ErrorBudget(NeuralFields& fields, const std::vector<Vec3>& X,
                         const std::vector<uint32_t>& samples, double mu,
                         const GaussNewtonOptions& inversion, const Latent& z0)
    : fields_(fields),
      points_(fields.prepare(X)),
      samples_(samples),
      mu_(mu),
      inversion_(inversion),
      g_(fields.sample_deformation(X, samples)),
      refiner_(std::make_unique<FrameLatentRefiner>(fields, X, TrainConfig().refine_latents)),
      z_(z0) {}

ErrorBudget::~ErrorBudget() = default;

void ErrorBudget::add(Sums& sums, const Latent& z, const std::vector<Vec3>& x,
                      const std::vector<Vec3>& v, const std::vector<Mat3>& tau,
                      const std::vector<Mat3>& C) {
  Latent zdot;  // the truth's latent velocity, for a τ or C that reads it
  const BasisDecoders* bases = fields_.bases();
  if (bases && bases->reads_velocity()) {
    std::vector<float> vf(3 * v.size());
    for (size_t p = 0; p < v.size(); ++p)
      for (int k = 0; k < 3; ++k) vf[3 * p + size_t(k)] = float(v[p][k]);
    zdot = bases->latent_velocity(z, vf.data());
  }
  fields_.deform(points_, z, gx_);
  fields_.stress(points_, z, mu_, tau_, &zdot);
  fields_.affine(points_, z, C_, mu_, &zdot);
  for (size_t p = 0; p < x.size(); ++p) {
    sums.x.add(gx_[p], x[p]);
    sums.stress.add(tau_[p], tau[p]);
    sums.affine.add(C_[p], C[p]);
  }
}

void ErrorBudget::add_frame(const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                            const std::vector<Mat3>& tau, const std::vector<Mat3>& C) {
  std::vector<float> xf(3 * x.size());
  for (size_t p = 0; p < x.size(); ++p)
    for (int k = 0; k < 3; ++k) xf[3 * p + size_t(k)] = float(x[p][k]);
  add(encoded_, refiner_->refine(xf.data(), fields_.encode(x)), x, v, tau, C);
  target_.resize(samples_.size());
  for (size_t s = 0; s < samples_.size(); ++s) target_[s] = x[samples_[s]];
  const InversionResult r = invert_deformation(*g_, target_, z_, inversion_);
  z_ = r.z;
  iterations_ += r.iterations;
  ++frames_;
  add(projected_, z_, x, v, tau, C);
}

ErrorBudgetResult ErrorBudget::result() const {
  ErrorBudgetResult r;
  r.encoded = encoded_.errors();
  r.projected = projected_.errors();
  r.projection_iterations = frames_ > 0 ? double(iterations_) / double(frames_) : 0.0;
  return r;
}

}  // namespace nsf
