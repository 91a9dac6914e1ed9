#pragma once
// A body's rigid motion, fitted to its particles: where a host attaches a camera, a sound or a
// rigid-body proxy to a deforming object (Runtime::object_pose, docs/EMBEDDING.md).
//
// With masses m_p, rest positions X_p and positions x_p now, about the centres of mass c₀ and c:
//   R   = the rotation of H = Σ m (x − c)(X − c₀)ᵀ (the polar factor; Kabsch's best fit, which
//         minimises Σ m ‖R (X − c₀) + c − x‖²),
//   v_c = Σ m v / M,   ω = I⁻¹ L with L = Σ m (x − c) × (v − v_c) and I the inertia about c,
// and the fit's mass-weighted rms misfit, how far the body is from a rigid copy of its rest shape.
#include <cstdint>
#include <vector>

#include "core/types.h"

namespace nsf {

struct BodyMotion {
  double mass = 0;
  Vec3 centre = Vec3::Zero();            // of mass, now
  Vec3 rest_centre = Vec3::Zero();       // of mass, at rest
  Mat3 rotation = Mat3::Identity();      // rest → now, about the centres of mass
  Vec3 velocity = Vec3::Zero();          // of the centre of mass
  Vec3 angular_velocity = Vec3::Zero();  // ω = I⁻¹ L (least squares where I is singular)
  double rms_misfit = 0;                 // of the rigid fit, metres
};

// Over the particles `members` (indices into X, x, v and mass; v may be empty: velocities zero).
// Throws nsf::Error for no members, mismatched sizes, a member out of range or no mass.
BodyMotion fit_body_motion(const std::vector<Vec3>& X, const std::vector<Vec3>& x,
                           const std::vector<Vec3>& v, const std::vector<double>& mass,
                           const std::vector<uint32_t>& members);

}  // namespace nsf
