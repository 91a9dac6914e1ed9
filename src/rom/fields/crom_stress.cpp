// CROM's stress (Figs. 5, 12, 13): τ = τ(F) with F = ∂g/∂X, through the scene's own constitutive
// models at each point's initial plastic state (the baseline has no plastic history).
#include "mpm/materials/material.h"
#include "rom/fields/network_fields.h"
#include "rom/fields/sources.h"

namespace nsf {

namespace {

class CromStress final : public PointFieldSource {
 public:
  explicit CromStress(const FieldContext& c) : c_(c), net_(c) {}
  std::string describe() const override { return "tau from dg/dX through the material (CROM)"; }
  void set_points() override { net_.set_points(); }
  void evaluate(const std::vector<uint32_t>& ids, const LatentPair& s, bool,
                std::vector<Mat3>& tau) override {
    net_.net().deformation_gradients(net_.points(), ids, s.z, F_);
    tau.resize(ids.size());
    for (size_t k = 0; k < ids.size(); ++k) {
      MaterialPoint mp = c_.points.mat0[ids[k]];
      tau[k] = c_.materials[c_.points.material[ids[k]]]->update(F_[k], mp, c_.dt);
    }
  }

 private:
  const FieldContext& c_;
  NetworkPoints net_;
  std::vector<Mat3> F_;
};

}  // namespace

std::unique_ptr<PointFieldSource> make_crom_stress(const FieldContext& c) {
  return std::make_unique<CromStress>(c);
}

}  // namespace nsf
