#include "rom/eval/error_budget.h"

#include <cmath>
#include <limits>

#include "nn/basis_decoders.h"
#include "nn/config.h"
#include "nn/network_samples.h"
#include "rom/step/rigid_frames.h"

namespace nsf {

namespace {
constexpr int kFramedFitIterations = 10;
}  // namespace

FieldErrors ErrorBudget::Sums::errors() const {
  FieldErrors e;
  if (x.ref > 0) e.delta = x.relative();
  if (stress.ref > 0) e.stress = stress.relative();
  if (affine.ref > 0) e.affine = affine.relative();
  return e;
}

ErrorBudget::ErrorBudget(NeuralFields& fields, const std::vector<Vec3>& X,
                         const std::vector<uint32_t>& samples, double mu,
                         const GaussNewtonOptions& inversion, const Latent& z0,
                         const RigidFrames* frames)
    : fields_(fields),
      points_(fields.prepare(X)),
      samples_(samples),
      mu_(mu),
      inversion_(inversion),
      g_(fields.sample_deformation(X, samples)),
      refiner_(std::make_unique<FrameLatentRefiner>(fields, X, TrainConfig().refine_latents)),
      frames_(frames && frames->on() ? frames : nullptr),
      z_(z0) {
  if (!frames_) return;
  g_ = in_rigid_frames(std::move(g_), *frames_, samples_);
  z_ = z_framed_ = frames_->augment(z0);
  all_ids_.resize(X.size());
  for (size_t p = 0; p < X.size(); ++p) all_ids_[p] = uint32_t(p);
  all_ = in_rigid_frames(fields.sample_deformation(X, all_ids_), *frames_, all_ids_);
}

ErrorBudget::~ErrorBudget() = default;

void ErrorBudget::add(Sums& sums, const Latent& z_all, const std::vector<Vec3>& x,
                      const std::vector<Vec3>& v, const std::vector<Mat3>& tau,
                      const std::vector<Mat3>& C) {
  const Latent z = frames_ ? frames_->model(z_all) : z_all;
  Latent zdot;  // the truth's latent velocity, for a τ or C that reads it (in the world's axes)
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
  if (frames_) {
    frames_->apply(nullptr, z_all, gx_);
    frames_->turn(all_ids_, z_all, tau_);
    frames_->turn(all_ids_, z_all, C_);
  }
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
  const Latent encoded = refiner_->refine(xf.data(), fields_.encode(x));
  add(encoded_, frames_ ? framed_fit(encoded, x) : encoded, x, v, tau, C);
  target_.resize(samples_.size());
  for (size_t s = 0; s < samples_.size(); ++s) target_[s] = x[samples_[s]];
  const InversionResult r = invert_deformation(*g_, target_, z_, inversion_);
  z_ = r.z;
  iterations_ += r.iterations;
  ++added_;
  add(projected_, z_, x, v, tau, C);
}

Latent ErrorBudget::framed_fit(const Latent& encoded, const std::vector<Vec3>& x) {
  const GaussNewtonOptions fit{kFramedFitIterations, 1e-7, false};
  InversionResult best;
  best.rms_residual = std::numeric_limits<double>::infinity();
  for (const Latent& start : {frames_->augment(encoded), z_framed_}) {
    InversionResult r = invert_deformation(*all_, x, start, fit);
    if (r.rms_residual < best.rms_residual) best = std::move(r);
  }
  return z_framed_ = best.z;
}

ErrorBudgetResult ErrorBudget::result() const {
  ErrorBudgetResult r;
  r.encoded = encoded_.errors();
  r.projected = projected_.errors();
  r.projection_iterations = added_ > 0 ? double(iterations_) / double(added_) : 0.0;
  return r;
}

}  // namespace nsf
