#pragma once
// The per-point basis of one field from the training frames (docs/TRAINING.md, "Decoder
// families"): rows are frames, columns every particle's components, the mean removed, and the
// modes are the first K right singular vectors. The SVD goes through the frames' Gram matrix
// (the method of snapshots): frames ≪ columns (hundreds against |P|·dim), so the Gram matrix is
// small and exact, and the columns are streamed through it in blocks, in double.
#include <Eigen/Core>
#include <functional>
#include <vector>

namespace nsf {

struct SnapshotBasis {
  Eigen::VectorXf mean;     // columns
  Eigen::MatrixXf modes;    // columns × K, in the field's own units (weights removed)
  Eigen::MatrixXf coeffs;   // frames × K: each training frame's projection (its best coefficients)
  Eigen::VectorXd sigma;    // the K singular values
  double total_energy = 0;  // Σ of all squared singular values (the frames' variance × frames)
  // Share of the training frames' variance beyond the K modes (their own projection error²).
  double residual_share() const;
};

// `fill(i, row)` writes frame i's `columns` values. `weights` (one per component, cycling over
// the columns) make the fit's norm the field's Frobenius norm (√2 on τ's off-diagonal entries);
// the coefficients are in that norm, the modes in the field's own units. K is clamped to the
// frames' rank (at most frames − 1). `max_matrix_bytes` (0: none) caps the frames × columns
// matrix held at once: above it the columns go through in slices, each a pass of `fill` over
// every frame for the Gram matrix and another for the modes (fill must give the same row each
// time); the Gram matrix, the mean and so the coefficients come out bit for bit the same.
SnapshotBasis fit_snapshot_basis(size_t frames, size_t columns,
                                 const std::function<void(size_t, float*)>& fill,
                                 const std::vector<double>& weights, int K,
                                 size_t max_matrix_bytes = 0);

}  // namespace nsf
