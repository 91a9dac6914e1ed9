#include "core/dense_kernels.h"

#include <cstring>

#include "core/isa.h"

namespace nsf {

namespace {

// Eight floats as one vector: two SSE registers in the baseline clone, one AVX register above.
typedef float simd8f __attribute__((vector_size(32)));

inline void load8(simd8f& v, const float* p) {
  std::memcpy(&v, p, sizeof v);
}

// The sum of a row's 16 partial sums, in a fixed order.
inline float lanes_sum(const simd8f& a, const simd8f& b) {
  const simd8f s = a + b;
  return ((s[0] + s[4]) + (s[1] + s[5])) + ((s[2] + s[6]) + (s[3] + s[7]));
}

}  // namespace

NSF_CLONES void rows_times_vectors(const float* B, int64_t rows, int K, const float* V, int cols,
                                   float* out) {
  if (K % 16 != 0) {  // untrained sizes: plain sums
    for (int64_t i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j) {
        float s = 0;
        for (int k = 0; k < K; ++k) s += B[i * K + k] * V[int64_t(j) * K + k];
        out[i * cols + j] = s;
      }
    return;
  }
  for (int64_t i = 0; i < rows; ++i) {
    const float* row = B + i * K;
    for (int j = 0; j < cols; ++j) {
      const float* v = V + int64_t(j) * K;
      simd8f a0 = {}, a1 = {}, x, y;
      for (int k = 0; k < K; k += 16) {
        load8(x, row + k), load8(y, v + k);
        a0 += x * y;
        load8(x, row + k + 8), load8(y, v + k + 8);
        a1 += x * y;
      }
      out[i * cols + j] = lanes_sum(a0, a1);
    }
  }
}

// Y's columns [j0, j0 + NC), eight rows at a time: each column of W is read once and scaled
// into 2·NC accumulators that stay in registers.
template <int NC>
__attribute__((always_inline)) inline void narrow_block(const double* W, int64_t m, int64_t n,
                                                        const double* X, int j0, double* Y) {
  int64_t i = 0;
  for (; i + 8 <= m; i += 8) {
    simd4 acc[NC][2] = {};
    for (int64_t k = 0; k < n; ++k) {
      simd4 w0, w1;
      load4(w0, W + k * m + i), load4(w1, W + k * m + i + 4);
      for (int c = 0; c < NC; ++c) {
        const double x = X[(j0 + c) * n + k];
        acc[c][0] += w0 * x, acc[c][1] += w1 * x;
      }
    }
    for (int c = 0; c < NC; ++c) {
      store4(Y + (j0 + c) * m + i, acc[c][0]);
      store4(Y + (j0 + c) * m + i + 4, acc[c][1]);
    }
  }
  for (; i < m; ++i)  // the last rows of a layer whose height is not a multiple of 8
    for (int c = 0; c < NC; ++c) {
      double s = 0;
      for (int64_t k = 0; k < n; ++k) s += W[k * m + i] * X[(j0 + c) * n + k];
      Y[(j0 + c) * m + i] = s;
    }
}

NSF_CLONES void narrow_product(const double* W, int64_t m, int64_t n, const double* X, int cols,
                               double* Y) {
  int j0 = 0;
  for (; j0 + 4 <= cols; j0 += 4) narrow_block<4>(W, m, n, X, j0, Y);
  switch (cols - j0) {
    case 3:
      return narrow_block<3>(W, m, n, X, j0, Y);
    case 2:
      return narrow_block<2>(W, m, n, X, j0, Y);
    case 1:
      return narrow_block<1>(W, m, n, X, j0, Y);
    default:
      return;
  }
}

}  // namespace nsf
