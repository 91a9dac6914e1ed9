#pragma once
// von Mises plasticity on StVK-Hencky elasticity with optional hardening and softening → damage
// (App. F.4, Wang et al. 2019). Softening is what lets the cake fracture.
#include "mpm/materials/material.h"

namespace nsf {

class VonMises : public Material {
 public:
  std::string type() const override { return "von_mises"; }
  // yield_stress τ_y bounds the Frobenius norm of the deviatoric Kirchhoff stress (Pa);
  // hardening ξ (dimensionless) and softening θ (Pa: τ_y drops by θ per unit plastic strain) are
  // optional, default 0.
  std::vector<std::string> parameter_names() const override {
    return {"E", "nu", "yield_stress", "hardening", "softening"};
  }
  MaterialPoint make_point(const ParamMap& params, const std::string& path) const override;
  Mat3 update(Mat3& F, MaterialPoint& mp, double dt) const override;
};

}  // namespace nsf
