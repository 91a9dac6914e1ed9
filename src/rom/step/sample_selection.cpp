#include "rom/step/sample_selection.h"

#include <algorithm>
#include <limits>

#include "core/error.h"

namespace nsf {

std::vector<Eigen::Index> qdeim_rows(const Eigen::MatrixXd& U) {
  if (U.cols() == 0 || U.rows() < U.cols())
    fail("qdeim: a basis of ", U.cols(), " columns over ", U.rows(), " rows");
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(U.transpose());
  const Eigen::Index k = std::min<Eigen::Index>(U.cols(), qr.rank());
  std::vector<Eigen::Index> rows(static_cast<size_t>(k));
  for (Eigen::Index i = 0; i < k; ++i) rows[size_t(i)] = qr.colsPermutation().indices()(i);
  return rows;
}

Eigen::MatrixXd leading_left_singular_vectors(const Eigen::MatrixXd& A, double energy) {
  // A is tall (3|P| rows, a few dozen columns): the eigenvectors of AᵀA give its right singular
  // vectors, and U = A V Σ⁻¹, without a factorisation of the tall matrix.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(A.transpose() * A);
  const Eigen::VectorXd lambda = eig.eigenvalues().reverse().cwiseMax(0.0);
  const Eigen::MatrixXd V = eig.eigenvectors().rowwise().reverse();
  const double total = lambda.sum();
  if (!(total > 0)) fail("the tangent directions of g are all zero: no sample can fix the latent");
  Eigen::Index k = 0;
  double kept = 0;
  while (k < lambda.size() && lambda(k) > 1e-12 * lambda(0) && (k == 0 || kept < energy * total))
    kept += lambda(k++);
  Eigen::MatrixXd U = A * V.leftCols(k);
  for (Eigen::Index j = 0; j < k; ++j) U.col(j) /= std::sqrt(lambda(j));
  return U;
}

std::vector<uint32_t> qdeim_particles(const Eigen::MatrixXd& U, const std::vector<uint32_t>& fill) {
  std::vector<uint32_t> out;
  std::vector<char> taken(size_t(U.rows() / 3), 0);
  const auto take = [&](uint32_t p) {
    if (p < taken.size() && !taken[p]) taken[p] = 1, out.push_back(p);
  };
  for (Eigen::Index row : qdeim_rows(U)) take(uint32_t(row / 3));
  for (uint32_t p : fill) take(p);
  return out;
}

double restricted_condition(const Eigen::MatrixXd& U, const std::vector<uint32_t>& particles) {
  Eigen::MatrixXd R(3 * Eigen::Index(particles.size()), U.cols());
  for (size_t i = 0; i < particles.size(); ++i)
    R.middleRows(3 * Eigen::Index(i), 3) = U.middleRows(3 * Eigen::Index(particles[i]), 3);
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(R);
  const Eigen::VectorXd s = svd.singularValues();
  if (s.size() < U.cols() || !(s(s.size() - 1) > 1e-14 * s(0)))
    return std::numeric_limits<double>::infinity();
  return s(0) / s(s.size() - 1);
}

}  // namespace nsf
