#pragma once
// Per-particle constitutive parameters and plastic state. Kept per particle (not per material) so
// weak elements, damage and hardening can vary in space. Kept small: nine doubles (72 bytes).

namespace nsf {

struct MaterialPoint {
  double mu = 0;            // shear modulus  mû = E / (2(1+ν))
  double lambda = 0;        // Lamé modulus   λ = Eν / ((1+ν)(1-2ν))
  double yield_stress = 0;  // current τ_y (von Mises) or σ_Y (Herschel–Bulkley); evolves
  double alpha = 0;         // Drucker–Prager: α = sqrt(2/3)·2 sin φ / (3 − sin φ)
  double hardening = 0;     // von Mises hardening coefficient ξ
  double softening = 0;     // von Mises softening coefficient θ
  double viscosity = 0;     // Herschel–Bulkley η
  double damaged = 0;       // 1 once softening drove τ_y to zero (Lamé parameters then zero)
  double cohesion = 0;      // Drucker–Prager: log-strain shift of the cone apex (0 = dry sand)
};

}  // namespace nsf
