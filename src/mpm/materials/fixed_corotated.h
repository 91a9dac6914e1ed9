#pragma once
// Fixed corotated elasticity (App. F.1): τ = 2μ(F − R)Fᵀ + λ(J − 1)J·I, R = UVᵀ.
#include "mpm/materials/material.h"

namespace nsf {

class FixedCorotated : public Material {
 public:
  std::string type() const override { return "fixed_corotated"; }
  std::vector<std::string> parameter_names() const override { return {"E", "nu"}; }
  MaterialPoint make_point(const ParamMap& params, const std::string& path) const override;
  Mat3 update(Mat3& F, MaterialPoint& mp, double dt) const override;
};

}  // namespace nsf
