#pragma once
// StVK elasticity with Hencky strain (App. F.2): τ = U (2μ ε + λ sum(ε) 1) Uᵀ, ε = log Σ.
#include "mpm/materials/material.h"

namespace nsf {

class StvkHencky : public Material {
 public:
  std::string type() const override { return "stvk_hencky"; }
  std::vector<std::string> parameter_names() const override { return {"E", "nu"}; }
  MaterialPoint make_point(const ParamMap& params, const std::string& path) const override;
  Mat3 update(Mat3& F, MaterialPoint& mp, double dt) const override;
};

}  // namespace nsf
