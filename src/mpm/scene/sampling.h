#pragma once
// Particle seeding: a regular lattice of ppc³ particles per grid cell, at the cell-centred
// sub-cell offsets (c + (a + ½)/ppc)·Δx, kept where the shape contains them. The lattice is
// anchored at the domain's lower corner, so objects sampled separately never overlap and a
// cell-aligned box yields exactly (cells · ppc)³ particles.
#include <vector>

#include "core/types.h"
#include "mpm/scene/geometry.h"

namespace nsf {

struct Lattice {
  Vec3 lo;        // domain lower corner
  Vec3 hi;        // domain upper corner; no point is placed beyond it
  double dx = 1;  // grid spacing
  int ppc = 2;    // particles per cell along each axis
  double spacing() const { return dx / ppc; }
  double particle_volume() const { return spacing() * spacing() * spacing(); }
};

// Lattice points inside `shape`, ordered by x index, then y, then z (deterministic: the particle
// index is the identity used by output files and the reduced model).
std::vector<Vec3> sample_shape(const Shape& shape, const Lattice& lattice);

}  // namespace nsf
