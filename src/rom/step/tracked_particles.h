#pragma once
// Each integration point's own state, kept as the full-order engine keeps every particle's, for
// the tracked field sources (docs/ROM.md): F^E and the plastic state, updated through the
// scene's material from the velocity gradient of the point's own G2P, its τ, and APIC's C. Every
// point of N goes through G2P while a tracked source is in use; a merged point of a thinned
// quadrature carries a state of its own, as a coarse engine's particle would. The state
// remembers the plastic path, which h's stress, a function of the latent, does not.
#include <memory>
#include <string>
#include <vector>

#include "core/types.h"
#include "mpm/material_point.h"

namespace nsf {

class Material;
struct Particles;
struct PointTable;

class TrackedParticles {
 public:
  TrackedParticles(std::vector<Mat3> F0, std::vector<MaterialPoint> mat0,
                   std::vector<uint16_t> material,
                   const std::vector<std::unique_ptr<Material>>& materials, double dt);

  // A source takes the state: `what` names it in errors (e.g. "--stress tracked");
  // `explicit_stress` when it integrates the material explicitly, so that the ROM step must keep to
  // the CFL bound. The first caller starts the state: τ of every point from its initial F.
  void enlist(const std::string& what, bool explicit_stress);
  bool active() const { return !what_.empty(); }

  // The point table changed (a thinned quadrature's merged points): each new merged point starts
  // from its group's mass-weighted F and its first member's plastic state. Throws nsf::Error
  // once the run has begun, when a merged point would lose its history (the ROM keeps its
  // quadrature for the whole run while the state is tracked).
  void set_points(const PointTable& table);

  // Throws nsf::Error when an explicit stress breaks the full-order CFL bound.
  void check(double cfl_bound) const;

  // After G2P: point ids[k] sits at row rows[k] of P, with its new F, C and velocity.
  void advance(const std::vector<uint32_t>& ids, const Particles& P,
               const std::vector<uint32_t>& rows);

  // An undo of the state since the last mark, for a guard that redoes a step
  // (rom/step/step_guard.h): after mark(), each advance first keeps the old state of the points it
  // is the first since the mark to change; rollback() puts them back (and may be repeated). Only
  // the newest mark's state is kept; before the first mark nothing is, and rollback() is false.
  void mark();
  bool rollback();
  // The step the material integrates over (a split step's substeps are shorter).
  void set_dt(double dt) { dt_ = dt; }

  // Point p's state; a particle merged into a quadrature point reads its group's.
  const Mat3& F(size_t p) const { return F_[at(p)]; }
  const Mat3& tau(size_t p) const { return tau_[at(p)]; }
  const Mat3& C(size_t p) const { return C_[at(p)]; }
  // Point p's velocity from its G2P in the last advance, if it went through that one (a point
  // that joined N since has none: nullptr).
  const Vec3* last_velocity(size_t p) const {
    const size_t i = at(p);
    return advances_ > 0 && advanced_in_[i] == advances_ ? &v_[i] : nullptr;
  }

 private:
  Mat3 update(size_t p);
  void keep_for_undo(const std::vector<uint32_t>& ids);
  size_t at(size_t p) const { return p < owner_.size() ? owner_[p] : p; }

  size_t particles_;  // the particles' ids come first, then the merged points'
  bool advanced_ = false;
  std::vector<uint32_t> owner_;  // per particle: the point that carries its state
  std::vector<Mat3> F_, tau_, C_;
  std::vector<Vec3> v_;
  std::vector<long> advanced_in_;  // per point: the advance it last went through (0: none)
  long advances_ = 0;
  std::vector<MaterialPoint> mp_;
  struct Kept {
    uint32_t p;
    Mat3 F, tau, C;
    Vec3 v;
    long advanced_in;
    MaterialPoint mp;
  };
  std::vector<Kept> undo_;                // since the newest mark
  std::vector<long> kept_in_;             // per point: the mark its state was kept under (0: none)
  long mark_ = 0, advances_at_mark_ = 0;  // mark_: marks so far
  std::vector<uint16_t> material_;
  const std::vector<std::unique_ptr<Material>>& materials_;
  double dt_;
  std::string what_;
  bool explicit_stress_ = false;
};

}  // namespace nsf
