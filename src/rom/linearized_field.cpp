#include "rom/linearized_field.h"

#include <torch/torch.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace nsf {

LinearizedField::LinearizedField(Network net, int64_t out_dim, torch::Tensor Xn_all,
                                 Eigen::VectorXd z_scale, double radius)
    : net_(std::move(net)),
      d_(out_dim),
      Xn_all_(std::move(Xn_all)),
      scale_(std::move(z_scale)),
      radius_(radius),
      slot_(size_t(Xn_all_.size(0)), -1) {
  if (!(radius > 0)) fail("linearised field: the anchor radius must be positive, got ", radius);
  for (int64_t i = 0; i < scale_.size(); ++i)
    if (!(scale_[i] > 0)) fail("linearised field: latent scales must be positive");
}

void LinearizedField::prepare(const std::vector<uint32_t>& ids, const Eigen::VectorXd& z) {
  bool moved = anchors_ == 0;
  for (int64_t i = 0; !moved && i < z.size(); ++i)
    moved = std::abs(z[i] - anchor_[i]) > radius_ * scale_[i];
  if (moved) {
    for (uint32_t p : owner_) slot_[p] = -1;
    owner_.clear(), coeffs_.clear();
    anchor_ = z;
    ++anchors_;
  }
  std::vector<uint32_t> missing;
  for (uint32_t p : ids)
    if (slot_[p] < 0) missing.push_back(p);
  if (!missing.empty()) expand(missing);
}

void LinearizedField::expand(const std::vector<uint32_t>& ids) {
  torch::NoGradGuard no_grad;
  const int64_t r = anchor_.size(), stride = d_ * (1 + r);
  // Chunks bound the batch (r + 1 rows per particle) to a few tens of MB of activations.
  constexpr size_t kChunk = 4096;
  for (size_t begin = 0; begin < ids.size(); begin += kChunk) {
    const size_t end = std::min(ids.size(), begin + kChunk);
    const int64_t m = int64_t(end - begin);
    torch::Tensor index = torch::empty({m}, torch::kInt64);
    int64_t* ip = index.data_ptr<int64_t>();
    for (int64_t k = 0; k < m; ++k) ip[k] = int64_t(ids[begin + size_t(k)]);
    const torch::Tensor Xn = Xn_all_.index_select(0, index);
    // Latent rows: the anchor for the first m, then the anchor moved along e_i for block i.
    torch::Tensor zs = torch::empty({(1 + r) * m, r}, torch::kFloat32);
    std::vector<double> steps(size_t(r), 0.0);
    for (int64_t i = 0; i <= r; ++i) {
      Eigen::VectorXd zi = anchor_;
      if (i > 0) {
        zi[i - 1] += kDifferenceStep * scale_[i - 1];
        // The step as float32 represents it: the network sees the rounded latent.
        steps[size_t(i - 1)] = double(float(zi[i - 1])) - double(float(anchor_[i - 1]));
      }
      const torch::Tensor row =
          torch::from_blob(zi.data(), {1, r}, torch::kFloat64).to(torch::kFloat32);
      zs.slice(0, i * m, (i + 1) * m).copy_(row.expand({m, r}));
    }
    const torch::Tensor out =
        net_(Xn.repeat({1 + r, 1}), zs).to(torch::kFloat64).contiguous();  // (1+r)m × d
    const double* o = out.data_ptr<double>();
    for (int64_t k = 0; k < m; ++k) {
      const uint32_t p = ids[begin + size_t(k)];
      slot_[p] = int32_t(owner_.size());
      owner_.push_back(p);
      const size_t base = coeffs_.size();
      coeffs_.resize(base + size_t(stride));
      double* c = &coeffs_[base];
      const double* f0 = o + k * d_;
      for (int64_t j = 0; j < d_; ++j) c[j] = f0[j];
      for (int64_t i = 0; i < r; ++i) {
        const double* fi = o + ((1 + i) * m + k) * d_;
        for (int64_t j = 0; j < d_; ++j) c[d_ + j * r + i] = (fi[j] - f0[j]) / steps[size_t(i)];
      }
    }
    expansions_ += m;
  }
}

void LinearizedField::evaluate(const std::vector<uint32_t>& ids, const Eigen::VectorXd& z,
                               std::vector<double>& out) const {
  const int64_t r = anchor_.size(), stride = d_ * (1 + r);
  const Eigen::VectorXd dz = z - anchor_;
  out.resize(ids.size() * size_t(d_));
  for (size_t k = 0; k < ids.size(); ++k) {
    const int32_t s = slot_[ids[k]];
    if (s < 0) fail("linearised field: particle ", ids[k], " was not prepared");
    const double* c = &coeffs_[size_t(s) * size_t(stride)];
    for (int64_t j = 0; j < d_; ++j) {
      double v = c[j];
      for (int64_t i = 0; i < r; ++i) v += c[d_ + j * r + i] * dz[i];
      out[k * size_t(d_) + size_t(j)] = v;
    }
  }
}

}  // namespace nsf
