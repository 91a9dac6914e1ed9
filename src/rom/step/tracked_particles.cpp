#include "rom/step/tracked_particles.h"

#include <numeric>

#include "core/error.h"
#include "mpm/materials/material.h"
#include "mpm/particles.h"
#include "rom/fields/field_source.h"
#include "rom/step/rom_diverged.h"

namespace nsf {

TrackedParticles::TrackedParticles(std::vector<Mat3> F0, std::vector<MaterialPoint> mat0,
                                   std::vector<uint16_t> material,
                                   const std::vector<std::unique_ptr<Material>>& materials,
                                   double dt)
    : particles_(F0.size()),
      F_(std::move(F0)),
      mp_(std::move(mat0)),
      material_(std::move(material)),
      materials_(materials),
      dt_(dt) {}

void TrackedParticles::enlist(const std::string& what, bool explicit_stress) {
  if (!active()) {
    C_.assign(F_.size(), Mat3::Zero());
    v_.assign(F_.size(), Vec3::Zero());
    advanced_in_.assign(F_.size(), 0);
    tau_.resize(F_.size());
    for (size_t p = 0; p < F_.size(); ++p) tau_[p] = update(p);
  }
  // The stress's name goes first in messages: it is the one with the stricter demands.
  what_ = explicit_stress || what_.empty() ? what : what_;
  explicit_stress_ = explicit_stress_ || explicit_stress;
}

void TrackedParticles::set_points(const PointTable& table) {
  const size_t n = table.X.size();
  if (!active() || n == F_.size()) return;
  if (advanced_)
    fail("rom: ", what_,
         " carries each integration point's own state, and the merged points of the thinned "
         "quadrature changed during the run (internal: the quadrature must stay fixed)");
  F_.resize(particles_), mp_.resize(particles_), material_.resize(particles_);
  owner_.resize(particles_);
  std::iota(owner_.begin(), owner_.end(), 0u);
  for (size_t j = 0; j + particles_ < n; ++j) {
    const auto& members = table.merged_members[j];
    Mat3 F = Mat3::Zero();
    for (const auto& [p, share] : members) {
      F += share * F_[p];
      owner_[p] = uint32_t(particles_ + j);
    }
    F_.push_back(F);
    mp_.push_back(table.mat0[particles_ + j]);
    material_.push_back(table.material[particles_ + j]);
  }
  C_.assign(n, Mat3::Zero());
  v_.assign(n, Vec3::Zero());
  advanced_in_.assign(n, 0);
  tau_.resize(n);
  for (size_t p = 0; p < n; ++p) tau_[p] = update(p);
}

void TrackedParticles::check(double cfl_bound) const {
  if (!active()) return;
  // Unlike h's stress, the tracked one is the explicit engine's and shares its bound.
  if (explicit_stress_ && dt_ > cfl_bound * (1 + 1e-9))
    fail_diverged("rom: ", what_, " integrates the material explicitly, so the ROM step ", dt_,
                  " s must stay within the CFL bound ", cfl_bound,
                  " s: lower --dt-ratio, take the step at the bound (--dt-ratio cfl) or raise the "
                  "scene's rom.cfl");
}

Mat3 TrackedParticles::update(size_t p) {
  return materials_[material_[p]]->update(F_[p], mp_[p], dt_);
}

void TrackedParticles::advance(const std::vector<uint32_t>& ids, const Particles& P,
                               const std::vector<uint32_t>& rows) {
  advanced_ = true;
  if (mark_ > 0) keep_for_undo(ids);
  ++advances_;
  const int64_t n = int64_t(ids.size());
  // Each point on its own: any thread count gives the same bits.
#pragma omp parallel for schedule(static) if (n > 512)
  for (int64_t k = 0; k < n; ++k) {
    const uint32_t p = ids[k];
    F_[p] = P.F[rows[k]];
    tau_[p] = update(p);
    C_[p] = P.C[rows[k]];
    v_[p] = P.v[rows[k]];
    advanced_in_[p] = advances_;
  }
}

void TrackedParticles::mark() {
  undo_.clear();
  advances_at_mark_ = advances_;
  ++mark_;
}

void TrackedParticles::keep_for_undo(const std::vector<uint32_t>& ids) {
  if (kept_in_.size() != F_.size()) kept_in_.assign(F_.size(), 0);
  for (uint32_t p : ids) {
    if (kept_in_[p] == mark_) continue;
    kept_in_[p] = mark_;
    undo_.push_back({p, F_[p], tau_[p], C_[p], v_[p], advanced_in_[p], mp_[p]});
  }
}

bool TrackedParticles::rollback() {
  if (mark_ == 0) return false;
  for (const Kept& k : undo_) {
    F_[k.p] = k.F, tau_[k.p] = k.tau, C_[k.p] = k.C, v_[k.p] = k.v;
    advanced_in_[k.p] = k.advanced_in, mp_[k.p] = k.mp;
    kept_in_[k.p] = 0;
  }
  undo_.clear();
  advances_ = advances_at_mark_;
  return true;
}

}  // namespace nsf
