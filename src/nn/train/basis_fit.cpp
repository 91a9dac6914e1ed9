// GCC 12 reports false -Wmaybe-uninitialized warnings from inside Eigen's kernels for
// dynamic-size products (in the intrinsics headers, not in this code).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include "nn/train/basis_fit.h"

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
                                 const std::vector<double>& weights, int K,
                                 size_t max_matrix_bytes) {
  if (frames < 2) fail("basis: need at least 2 training frames, got ", frames);
  if (weights.empty() || columns % weights.size() != 0)
    fail("basis: ", columns, " columns are not a whole number of ", weights.size(), "-vectors");
  // A: frames × columns, float, weighted, mean removed; held a slice of columns at a time (a
  // multiple of the Gram blocks, so that G sums the same blocks in the same order) when the
  // whole matrix would pass max_matrix_bytes. Each slice then costs a pass of fill over the
  // frames, twice: for G, and for the modes.
  constexpr size_t kBlock = 8192;
  using Matrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  size_t slice = columns;
  if (max_matrix_bytes > 0 && frames * columns * sizeof(float) > max_matrix_bytes)
    slice = std::max<size_t>(1, max_matrix_bytes / (frames * sizeof(float) * kBlock)) * kBlock;
  SnapshotBasis b;
  b.mean.resize(Eigen::Index(columns));
  const size_t d = weights.size();
  std::vector<float> row(slice < columns ? columns : 0);
  Matrix A;
  // Columns [c0, c0 + n) of every frame into A, the mean removed (computed on the first pass),
  // weighted.
  const auto load = [&](size_t c0, size_t n, bool first_pass) {
    A.resize(Eigen::Index(frames), Eigen::Index(n));
    for (size_t i = 0; i < frames; ++i) {
      if (n == columns) {
        fill(i, A.row(Eigen::Index(i)).data());
        continue;
      }
      fill(i, row.data());
      std::copy_n(row.data() + c0, n, A.row(Eigen::Index(i)).data());
    }
    if (first_pass) b.mean.segment(Eigen::Index(c0), Eigen::Index(n)) = A.colwise().mean();
    A.rowwise() -= b.mean.segment(Eigen::Index(c0), Eigen::Index(n)).transpose();
    for (size_t c = 0; c < n; ++c)
      if (weights[(c0 + c) % d] != 1.0) A.col(Eigen::Index(c)) *= float(weights[(c0 + c) % d]);
  };
  // G = A Aᵀ in double, a block of columns at a time.
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(frames, frames);
  for (size_t s0 = 0; s0 < columns; s0 += slice) {
    const size_t sn = std::min(slice, columns - s0);
    load(s0, sn, true);
    for (size_t c0 = 0; c0 < sn; c0 += kBlock) {
      const size_t n = std::min(kBlock, sn - c0);
      const Eigen::MatrixXd block = A.middleCols(Eigen::Index(c0), Eigen::Index(n)).cast<double>();
      G.noalias() += block * block.transpose();
    }
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
  if (slice == columns) {
    b.modes = A.transpose() * W;
  } else {
    A = Matrix();  // the last slice's memory, before the modes take theirs
    b.modes.resize(Eigen::Index(columns), k);
    for (size_t s0 = 0; s0 < columns; s0 += slice) {
      const size_t sn = std::min(slice, columns - s0);
      load(s0, sn, false);
      b.modes.middleRows(Eigen::Index(s0), Eigen::Index(sn)) = A.transpose() * W;
    }
  }
  for (size_t c = 0; c < columns; ++c)
    if (weights[c % d] != 1.0) b.modes.row(Eigen::Index(c)) /= float(weights[c % d]);
  b.coeffs = (Uk * b.sigma.asDiagonal()).cast<float>();
  return b;
}

}  // namespace nsf
