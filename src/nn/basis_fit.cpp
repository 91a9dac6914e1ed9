// GCC 12 reports false -Wmaybe-uninitialized warnings from inside Eigen's kernels for
// dynamic-size products (in the intrinsics headers, not in this code).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include "nn/basis_fit.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace nsf {

double SnapshotBasis::residual_share() const {
  return total_energy > 0 ? std::max(0.0, 1.0 - sigma.squaredNorm() / total_energy) : 0.0;
}

SnapshotBasis fit_snapshot_basis(size_t frames, size_t columns,
                                 const std::function<void(size_t, float*)>& fill,
                                 const std::vector<double>& weights, int K) {
  if (frames < 2) fail("basis: need at least 2 training frames, got ", frames);
  if (weights.empty() || columns % weights.size() != 0)
    fail("basis: ", columns, " columns are not a whole number of ", weights.size(), "-vectors");
  // A: frames × columns, float, weighted, mean removed.
  Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> A(frames, columns);
  for (size_t i = 0; i < frames; ++i) fill(i, A.row(Eigen::Index(i)).data());
  SnapshotBasis b;
  b.mean = A.colwise().mean().transpose();
  A.rowwise() -= b.mean.transpose();
  const size_t d = weights.size();
  for (size_t c = 0; c < columns; ++c)
    if (weights[c % d] != 1.0) A.col(Eigen::Index(c)) *= float(weights[c % d]);
  // G = A Aᵀ in double, a block of columns at a time.
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(frames, frames);
  constexpr size_t kBlock = 8192;
  for (size_t c0 = 0; c0 < columns; c0 += kBlock) {
    const size_t n = std::min(kBlock, columns - c0);
    const Eigen::MatrixXd block = A.middleCols(Eigen::Index(c0), Eigen::Index(n)).cast<double>();
    G.noalias() += block * block.transpose();
  }
  b.total_energy = G.trace();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(G);
  if (eig.info() != Eigen::Success) fail("basis: the eigensolver of the Gram matrix failed");
  // Largest first; keep those above the round-off of the largest.
  const Eigen::VectorXd lambda = eig.eigenvalues().reverse();
  const Eigen::MatrixXd U = eig.eigenvectors().rowwise().reverse();
  int k = std::min<int>(K, int(frames) - 1);
  while (k > 1 && !(lambda[k - 1] > 1e-12 * lambda[0])) --k;
  b.sigma = lambda.head(k).cwiseMax(0.0).cwiseSqrt();
  const Eigen::MatrixXd Uk = U.leftCols(k);
  // Modes V = Aᵀ U Σ⁻¹ (orthonormal in the weighted norm), coefficients A V = U Σ.
  const Eigen::MatrixXf W = (Uk * b.sigma.cwiseInverse().asDiagonal()).cast<float>();
  b.modes = A.transpose() * W;
  for (size_t c = 0; c < columns; ++c)
    if (weights[c % d] != 1.0) b.modes.row(Eigen::Index(c)) /= float(weights[c % d]);
  b.coeffs = (Uk * b.sigma.asDiagonal()).cast<float>();
  return b;
}

}  // namespace nsf
