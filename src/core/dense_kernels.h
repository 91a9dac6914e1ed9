#pragma once
// The small dense products of the reduced-order step, as cloned kernels (core/isa.h): a basis
// model's fields and Jacobians at the points (float rows times a few coefficient vectors) and its
// coefficient networks (a double layer times its input and the input's few derivative columns).
// Eigen picks its packets when a file is compiled, so in a portable build its products run at the
// baseline's width; and at these sizes (K = 32–128 columns, ≤ 8 right-hand sides) its general
// product spends as long packing as multiplying. These read each matrix once, without packing.
#include <cstdint>

namespace nsf {

// out[i·cols + j] = Σ_k B[i·K + k] · V[j·K + k] for i < rows, j < cols: rows of B (row-major,
// K columns) against cols vectors of K (V, one after another). Each sum runs over 16 interleaved
// partial sums, added at the end, whatever the CPU: every clone gives the same bits up to the
// rounding of fused multiply-adds.
void rows_times_vectors(const float* B, int64_t rows, int K, const float* V, int cols, float* out);

// Y = W X: W m × n, X n × cols, Y m × cols, all column-major (Eigen's default), cols small.
void narrow_product(const double* W, int64_t m, int64_t n, const double* X, int cols, double* Y);

}  // namespace nsf
