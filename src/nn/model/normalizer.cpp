#include "nn/model/normalizer.h"

#include <algorithm>
#include <cmath>

namespace nsf {

namespace {

torch::Tensor to_tensor(const std::vector<double>& v) {
  std::vector<float> f(v.begin(), v.end());
  return torch::tensor(f, torch::kFloat32);
}

}  // namespace

Normalizer Normalizer::identity(int64_t dim) {
  return {torch::zeros({dim}, torch::kFloat32), torch::ones({dim}, torch::kFloat32)};
}

Normalizer Normalizer::from_moments(const std::vector<double>& sum,
                                    const std::vector<double>& sum_sq, double count) {
  const size_t d = sum.size();
  std::vector<double> mean(d), sd(d);
  double largest = 0;
  for (size_t i = 0; i < d; ++i) {
    mean[i] = count > 0 ? sum[i] / count : 0.0;
    const double var = count > 0 ? sum_sq[i] / count - mean[i] * mean[i] : 0.0;
    sd[i] = std::sqrt(std::max(var, 0.0));
    largest = std::max(largest, sd[i]);
  }
  for (double& s : sd)
    if (!(s > 1e-6 * largest) || s < 1e-30) s = largest > 1e-30 ? largest : 1.0;
  return {to_tensor(mean), to_tensor(sd)};
}

}  // namespace nsf
