#pragma once
// A thinned quadrature for the ROM's MPM step (beyond the paper). The step on N is a quadrature
// of the grid's mass, momentum and stress-force integrals over the body; the paper takes every
// particle of N as a quadrature point. The fields g, h and l are continuous in X, so the
// integrals can use fewer points: per grid cell of the rest shape (and per material) keep
// `per_cell` particles, with the cell's mass and volume shared among them. Mass is conserved cell
// by cell; inference, the candidate set K and N all shrink by the thinning factor. The sample
// particles S are always kept, so every node of their stencils carries their own mass.
#include <cstdint>
#include <vector>

#include "core/types.h"

namespace nsf {

struct ThinnedQuadrature {
  std::vector<uint32_t> ids;  // the kept particles Q, ascending
  // Per particle of P: its quadrature mass and volume (the cell's share for Q, 0 elsewhere).
  std::vector<double> mass, vol0;
};

// Keeps all of `keep` plus, per (cell, material) bin, particles up to `per_cell` chosen to spread
// through the bin (farthest-point order from the one nearest the bin's centroid). per_cell ≤ 0
// keeps every particle with its own mass and volume. Throws nsf::Error on mismatched sizes.
ThinnedQuadrature thin_quadrature(const std::vector<Vec3>& X, const std::vector<double>& mass,
                                  const std::vector<double>& vol0,
                                  const std::vector<uint16_t>& material, const Vec3& lo, double dx,
                                  int per_cell, const std::vector<uint32_t>& keep);

}  // namespace nsf
