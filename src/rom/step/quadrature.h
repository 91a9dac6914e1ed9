#pragma once
// A thinned quadrature for the ROM's MPM step (beyond the paper). The step on N is a quadrature
// of the grid's mass, momentum and stress-force integrals over the body; the paper takes every
// particle of N as a quadrature point. The fields g, h and l are continuous in X, so they can be
// queried anywhere in the rest shape and the integrals can use fewer points: per grid cell of the
// rest shape (and per material) the particles are merged into `per_cell` groups, each replaced by
// one point at its centre of mass carrying the group's mass and volume. Mass, and the first
// moment of the rest shape, are conserved cell by cell. The sample particles S stay themselves,
// so each node of their stencils carries their own mass, and G2P can move them.
#include <cstdint>
#include <utility>
#include <vector>

#include "core/types.h"
#include "mpm/material_point.h"

namespace nsf {

// Quadrature points are numbered after the particles: id p < |P| is particle p itself, id |P| + j
// is the merged point j.
struct ThinnedQuadrature {
  std::vector<uint32_t> ids;  // the quadrature points, ascending
  // Per id (|P| + merged points): quadrature mass and volume, 0 for particles merged away.
  std::vector<double> mass, vol0;
  std::vector<Vec3> merged_X;          // rest position of merged point j (its group's centroid)
  std::vector<uint32_t> merged_group;  // a particle of merged point j's group (its material)
  // The particles of merged point j's group with their shares of its mass (summing to 1).
  std::vector<std::vector<std::pair<uint32_t, double>>> merged_members;
  size_t particles = 0;  // |P|
  bool thinned() const { return !merged_X.empty(); }
};

// Keeps all of `keep` as they are and merges the other particles of each (cell, material) bin
// into `per_cell` groups (seeds spread by farthest-point order, every particle to its nearest
// seed). per_cell ≤ 0 keeps every particle with its own mass and volume. Throws nsf::Error on
// mismatched sizes or a particle to keep that does not exist.
ThinnedQuadrature thin_quadrature(const std::vector<Vec3>& X, const std::vector<double>& mass,
                                  const std::vector<double>& vol0,
                                  const std::vector<uint16_t>& material, const Vec3& lo, double dx,
                                  int per_cell, const std::vector<uint32_t>& keep);

// Merged point j's material (its members from merged_members[j], `representative` from
// merged_group[j], the particles' materials `mat`): the group's moduli and yield stress,
// mass-weighted (the Voigt average), so that a cell of weak and sound particles (a weak region's
// edge, scattered weak elements) is as stiff as its particles are on average, not as one of them.
// The rest of the state is the representative's; a group of one material is it exactly.
MaterialPoint merged_material(const std::vector<std::pair<uint32_t, double>>& members,
                              uint32_t representative, const std::vector<MaterialPoint>& mat);

}  // namespace nsf
