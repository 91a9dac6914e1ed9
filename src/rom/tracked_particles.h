#pragma once
// Every particle's own state, kept as the full-order engine keeps it, for the tracked field
// sources (an ablation of h and l, docs/ROM.md): F^E and the plastic state, updated through the
// scene's material from the velocity gradient of the particle's own G2P, its τ, and APIC's C.
// The state is every particle's, so every particle must be a sample at every step (N = S = P).
#include <memory>
#include <string>
#include <vector>

#include "core/types.h"
#include "mpm/material_point.h"

namespace nsf {

class Material;
struct Particles;

class TrackedParticles {
 public:
  TrackedParticles(std::vector<Mat3> F0, std::vector<MaterialPoint> mat0,
                   std::vector<uint16_t> material,
                   const std::vector<std::unique_ptr<Material>>& materials, double dt);

  // A source takes the state: `what` names it in errors (e.g. "--stress tracked");
  // `explicit_stress` when it integrates the material explicitly, so that the ROM step must keep to
  // the CFL bound. The first caller starts the state: τ of every particle from its initial F.
  void enlist(const std::string& what, bool explicit_stress);
  bool active() const { return !what_.empty(); }

  // Throws nsf::Error unless every particle is a sample at every step, nothing is merged, and an
  // explicit stress keeps to the bound.
  void check(int samples, bool sample_schedule, bool thinned, double cfl_bound) const;

  // After G2P: particle S[k] sits at row gather[k] of P, with its new F and C.
  void advance(const std::vector<uint32_t>& S, const Particles& P,
               const std::vector<uint32_t>& gather);

  const Mat3& F(size_t p) const { return F_[p]; }
  const Mat3& tau(size_t p) const { return tau_[p]; }
  const Mat3& C(size_t p) const { return C_[p]; }

 private:
  Mat3 update(size_t p);

  std::vector<Mat3> F_, tau_, C_;
  std::vector<MaterialPoint> mp_;
  std::vector<uint16_t> material_;
  const std::vector<std::unique_ptr<Material>>& materials_;
  double dt_;
  std::string what_;
  bool explicit_stress_ = false;
};

}  // namespace nsf
