#pragma once
// Herschel–Bulkley viscoplasticity with h = 1 (App. F.5, Yue et al. 2015): toothpaste and other
// yield-stress fluids.
#include "mpm/materials/material.h"

namespace nsf {

class HerschelBulkley : public Material {
 public:
  std::string type() const override { return "herschel_bulkley"; }
  // yield_stress σ_Y (Pa, ≥ 0) and viscosity η (Pa·s, ≥ 0; 0 = rate-independent plasticity).
  std::vector<std::string> parameter_names() const override {
    return {"E", "nu", "yield_stress", "viscosity"};
  }
  MaterialPoint make_point(const ParamMap& params, const std::string& path) const override;
  Mat3 update(Mat3& F, MaterialPoint& mp, double dt) const override;
};

}  // namespace nsf
