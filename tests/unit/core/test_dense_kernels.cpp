// The reduced-order step's dense kernels (core/dense_kernels.h) against Eigen's products, at the
// shapes the models use and at the awkward ones (K not a multiple of 16, heights not a multiple
// of 8, one to nine right-hand sides).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <random>

#include "core/dense_kernels.h"
#include "core/isa.h"

namespace {

using RowMajorXf = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

TEST(DenseKernels, RowsTimesVectorsIsTheRowsProduct) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  for (int K : {16, 32, 64, 128, 5, 24})
    for (int64_t rows : {1, 3, 9, 600})
      for (int cols : {1, 2, 6}) {
        RowMajorXf B(rows, K);
        Eigen::MatrixXf V(K, cols);  // column j is vector j, contiguous
        for (float& x : B.reshaped()) x = u(rng);
        for (float& x : V.reshaped()) x = u(rng);
        RowMajorXf out(rows, cols);
        nsf::rows_times_vectors(B.data(), rows, K, V.data(), cols, out.data());
        const RowMajorXf expected = (B.cast<double>() * V.cast<double>()).cast<float>();
        // Sums of K products of numbers within ±1, in float: a few ulps of √K.
        EXPECT_LT((out - expected).cwiseAbs().maxCoeff(), 2e-6f * K)
            << "K " << K << ", rows " << rows << ", cols " << cols << " on " << nsf::kernel_isa();
      }
}

TEST(DenseKernels, NarrowProductIsTheMatrixProduct) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int64_t m : {1, 7, 8, 13, 128})
    for (int64_t n : {1, 5, 128})
      for (int cols = 1; cols <= 9; ++cols) {
        Eigen::MatrixXd W(m, n), X(n, cols), Y(m, cols);
        for (double& x : W.reshaped()) x = u(rng);
        for (double& x : X.reshaped()) x = u(rng);
        Y.setConstant(1e300);  // every entry must be written
        nsf::narrow_product(W.data(), m, n, X.data(), cols, Y.data());
        EXPECT_LT((Y - W * X).cwiseAbs().maxCoeff(), 1e-13 * double(n))
            << m << " × " << n << " times " << cols << " columns on " << nsf::kernel_isa();
      }
}

}  // namespace
