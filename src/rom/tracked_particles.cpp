#include "rom/tracked_particles.h"

#include "core/error.h"
#include "mpm/materials/material.h"
#include "mpm/particles.h"

namespace nsf {

TrackedParticles::TrackedParticles(std::vector<Mat3> F0, std::vector<MaterialPoint> mat0,
                                   std::vector<uint16_t> material,
                                   const std::vector<std::unique_ptr<Material>>& materials,
                                   double dt)
    : F_(std::move(F0)),
      mp_(std::move(mat0)),
      material_(std::move(material)),
      materials_(materials),
      dt_(dt) {}

void TrackedParticles::enlist(const std::string& what, bool explicit_stress) {
  if (!active()) {
    C_.assign(F_.size(), Mat3::Zero());
    tau_.resize(F_.size());
    for (size_t p = 0; p < F_.size(); ++p) tau_[p] = update(p);
  }
  // The stress's name goes first in messages: it is the one with the stricter demands.
  what_ = explicit_stress || what_.empty() ? what : what_;
  explicit_stress_ = explicit_stress_ || explicit_stress;
}

void TrackedParticles::check(int samples, bool sample_schedule, bool thinned,
                             double cfl_bound) const {
  if (!active()) return;
  const size_t np = F_.size();
  if (size_t(samples) != np || sample_schedule)
    fail("rom: ", what_, " keeps every particle's own state, so every particle must be a sample: ",
         "use --samples ", np, " (|P|) and no sample schedule");
  if (thinned) fail("rom: ", what_, " does not combine with --quadrature or the tangent cache");
  // Unlike h's stress, the tracked one is the explicit engine's and shares its bound.
  if (explicit_stress_ && dt_ > cfl_bound * (1 + 1e-9))
    fail("rom: ", what_, " integrates the material explicitly, so the ROM step ", dt_,
         " s must stay within the full-order CFL bound ", cfl_bound, " s: lower --dt-ratio");
}

Mat3 TrackedParticles::update(size_t p) {
  return materials_[material_[p]]->update(F_[p], mp_[p], dt_);
}

void TrackedParticles::advance(const std::vector<uint32_t>& S, const Particles& P,
                               const std::vector<uint32_t>& gather) {
  for (size_t k = 0; k < S.size(); ++k) {
    const uint32_t p = S[k];
    F_[p] = P.F[gather[k]];
    tau_[p] = update(p);
    C_[p] = P.C[gather[k]];
  }
}

}  // namespace nsf
