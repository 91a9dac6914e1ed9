#pragma once
// Sample particles chosen for the inversion rather than at random (issue #55; libROM's
// hyper-reduction: one free function per method over a basis of the quantity to be fitted). The
// Gauss–Newton fit of ẑ to the samples' positions is well-posed when ∂g/∂ẑ restricted to S is well
// conditioned; random samples may miss a motion only a few particles make (a plate's contact, a
// cut), and then a latent direction is fixed by noise.
#include <Eigen/Dense>
#include <cstdint>
#include <vector>

namespace nsf {

// QDEIM (Drmač & Gugercin 2016): the rows of U (n × k) picked by a column-pivoted QR of Uᵀ, in
// pivot order, at most k of them. U's columns span the fitted quantity's variations (here g's
// tangent directions over the training latents); the picked rows keep U's restriction to them
// invertible with a bounded condition number.
std::vector<Eigen::Index> qdeim_rows(const Eigen::MatrixXd& U);

// An orthonormal basis of the column space of A (n × m), its columns ordered by singular value:
// as many as hold `energy` of A's squared Frobenius norm (at least one).
Eigen::MatrixXd leading_left_singular_vectors(const Eigen::MatrixXd& A, double energy);

// Particles in the order they join S: the particles of QDEIM's rows of U (row 3p + c belongs to
// particle p), each once, then the rest of `fill` (another ranking of every particle, random or
// clustered) in its order, so that a larger S adds coverage to a well-posed core.
std::vector<uint32_t> qdeim_particles(const Eigen::MatrixXd& U, const std::vector<uint32_t>& fill);

// The condition number σ_max/σ_min of U's rows that belong to `particles` (3 rows each); +∞ when
// they do not fix every column.
double restricted_condition(const Eigen::MatrixXd& U, const std::vector<uint32_t>& particles);

}  // namespace nsf
