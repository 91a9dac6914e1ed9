#pragma once
// Helpers of the sources that evaluate the paper's coordinate networks f(X, ẑ) at the rest
// positions of the requested points (network, tangent, CROM, velocity). Torch level.
#include <torch/types.h>

#include <vector>

#include "rom/field_source.h"

namespace nsf {

class NeuralModel;

// The point table's rest positions, normalised as the networks take them (|points| × 3, float).
torch::Tensor normalised_points(const NeuralModel& model, const PointTable& points);
torch::Tensor index_tensor(const std::vector<uint32_t>& ids);
torch::Tensor latent_row(const Latent& z);                     // 1 × r, float
void to_vec3(const torch::Tensor& t, std::vector<Vec3>& out);  // rows of an n × 3 tensor
// Rows of an n × 6 tensor (xx yy zz xy yz xz, the run files' order) as symmetric matrices, or
// of an n × 9 tensor (row-major) as matrices.
void symmetric_rows(const torch::Tensor& t, std::vector<Mat3>& out);
void matrix_rows(const torch::Tensor& t, std::vector<Mat3>& out);

}  // namespace nsf
