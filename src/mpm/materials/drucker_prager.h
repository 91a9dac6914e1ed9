#pragma once
// Drucker–Prager plasticity for sand on StVK-Hencky elasticity (App. F.3, Klár et al. 2016).
#include "mpm/materials/material.h"

namespace nsf {

class DruckerPrager : public Material {
 public:
  std::string type() const override { return "drucker_prager"; }
  // friction_angle φ_f in degrees, in (0, 90). cohesion (optional, default 0) is a log-strain
  // shift of the cone apex: the material then sustains a volumetric stretch up to e^cohesion per
  // axis before it loses all stress (the convention of Ziran's DruckerPragerStvkHencky).
  std::vector<std::string> parameter_names() const override {
    return {"E", "nu", "friction_angle", "cohesion"};
  }
  MaterialPoint make_point(const ParamMap& params, const std::string& path) const override;
  Mat3 update(Mat3& F, MaterialPoint& mp, double dt) const override;
};

}  // namespace nsf
