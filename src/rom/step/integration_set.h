#pragma once
// The grid nodes I and integration particles N of §5.4:
//   I = { nodes i : N_i(x_p) ≠ 0 for some sample particle p ∈ S },
//   N = { particles p : N_i(x_p) ≠ 0 for some i ∈ I }.
// One MPM step over N gives S exactly the positions a full-order step over all of P would give
// (test_rom_integration_set). Finding N by this definition needs every particle's position, i.e.
// g on all of P per step, which would cost more than the full-order engine; CandidateSet keeps a
// superset K ⊇ N cheap to re-evaluate and says when it must be rebuilt from all positions.
#include <cstdint>
#include <vector>

#include "core/types.h"

namespace nsf {

// Flags over the nodes of a grid (lo, dx, dims), cleared through the list of set flags so that
// a step costs what it touches, not the grid size.
class NodeMarks {
 public:
  NodeMarks(const Vec3& lo, double dx, const Vec3i& dims);

  void clear();
  // Marks the 3×3×3 quadratic-B-spline stencil of every position, widened by `halo` nodes on
  // each side (halo 0: exactly the nodes with N_i(x) ≠ 0).
  void mark_stencils(const std::vector<Vec3>& x, int halo = 0);
  // True if a node of x's stencil is marked.
  bool touches(const Vec3& x) const;
  size_t count() const { return set_.size(); }

 private:
  void stencil_base(const Vec3& x, int base[3]) const;  // clamped into the grid
  Vec3 lo_;
  double inv_dx_;
  Vec3i dims_;
  std::vector<uint8_t> flag_;
  std::vector<uint32_t> set_;
};

// N by the definition: the indices into x (all particles) whose stencil touches I(S).
std::vector<uint32_t> integration_particles(const NodeMarks& I, const std::vector<Vec3>& x);

// Candidates K ⊇ N between refreshes. At a refresh (all positions known), K is every particle
// whose stencil touches I widened by `halo` nodes. Later steps evaluate only K; N ⊆ K holds
// while no particle has moved more than (halo − 1)/2 cells since the refresh, which `drift`
// checks on K itself (particles outside K are assumed to move no faster than those inside, the
// one assumption of the scheme; the brute-force test checks it along whole runs).
class CandidateSet {
 public:
  explicit CandidateSet(int halo = 3) : halo_(halo) {}

  // Rebuilds K from the positions of the particles that can join N and the sample positions.
  // x[k] is the position of particle ids[k] (ids null: of particle k, every particle).
  void refresh(NodeMarks& scratch, const std::vector<Vec3>& x, const std::vector<Vec3>& samples,
               const std::vector<uint32_t>* ids = nullptr);
  // True if positions of K now (same order as ids()) have drifted too far from the refresh.
  bool stale(const std::vector<Vec3>& x_now, double dx) const;

  const std::vector<uint32_t>& ids() const { return ids_; }
  // Positions of K at the refresh (same order as ids()).
  const std::vector<Vec3>& refresh_positions() const { return x_ref_; }
  int halo() const { return halo_; }
  bool empty() const { return ids_.empty(); }

 private:
  int halo_;
  std::vector<uint32_t> ids_;
  std::vector<Vec3> x_ref_;  // positions of K at the refresh
};

}  // namespace nsf
