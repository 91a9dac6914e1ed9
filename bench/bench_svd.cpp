// ns per 3×3 SVD: nsf::svd3 against Eigen::JacobiSVD, on general matrices and on the near-rotation
// deformation gradients an MPM step actually sees; and the fast polar rotation (core/polar3.h).
#include <benchmark/benchmark.h>

#include <Eigen/SVD>
#include <random>
#include <vector>

#include "core/polar3.h"
#include "core/svd3.h"

namespace {

using nsf::Mat3;
using nsf::Vec3;

std::vector<Mat3> make_inputs(bool near_rotation) {
  std::mt19937_64 rng(42);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<Mat3> out(1024);
  for (auto& F : out) {
    for (int i = 0; i < 9; ++i) F.data()[i] = n(rng);
    if (near_rotation) {
      Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
      F = q.normalized().toRotationMatrix() * (Mat3::Identity() + 0.05 * F);
    }
  }
  return out;
}

template <bool NearRotation>
void BM_svd3(benchmark::State& state) {
  const auto inputs = make_inputs(NearRotation);
  Mat3 U, V;
  Vec3 s;
  size_t i = 0;
  for (auto _ : state) {
    nsf::svd3(inputs[i++ & 1023], U, s, V);
    benchmark::DoNotOptimize(U);
    benchmark::DoNotOptimize(V);
    benchmark::DoNotOptimize(s);
  }
}

// The fixed-corotated fast path: R and J only, Newton polar iteration (falls back to svd3 when it
// declines, which never happens on these inputs).
void BM_fast_polar(benchmark::State& state) {
  const auto inputs = make_inputs(true);
  Mat3 R;
  double J;
  size_t i = 0;
  for (auto _ : state) {
    const Mat3& F = inputs[i++ & 1023];
    if (!nsf::fast_polar_rotation(F, R, J)) {
      Mat3 U, V;
      Vec3 s;
      nsf::svd3(F, U, s, V);
      R = U * V.transpose();
    }
    benchmark::DoNotOptimize(R);
    benchmark::DoNotOptimize(J);
  }
}

template <bool NearRotation>
void BM_eigen_jacobi(benchmark::State& state) {
  const auto inputs = make_inputs(NearRotation);
  size_t i = 0;
  for (auto _ : state) {
    Eigen::JacobiSVD<Mat3> svd(inputs[i++ & 1023], Eigen::ComputeFullU | Eigen::ComputeFullV);
    benchmark::DoNotOptimize(svd.matrixU());
    benchmark::DoNotOptimize(svd.matrixV());
    benchmark::DoNotOptimize(svd.singularValues());
  }
}

BENCHMARK_TEMPLATE(BM_svd3, false)->Name("svd3/gaussian");
BENCHMARK_TEMPLATE(BM_eigen_jacobi, false)->Name("eigen_jacobi/gaussian");
BENCHMARK_TEMPLATE(BM_svd3, true)->Name("svd3/near_rotation");
BENCHMARK_TEMPLATE(BM_eigen_jacobi, true)->Name("eigen_jacobi/near_rotation");
BENCHMARK(BM_fast_polar)->Name("fast_polar/near_rotation");

}  // namespace

BENCHMARK_MAIN();
