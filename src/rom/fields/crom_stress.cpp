// CROM's stress (Figs. 5, 12, 13): τ = τ(F) with F = ∂g/∂X, through the scene's own constitutive
// models at each point's initial plastic state (the baseline has no plastic history).
#include <torch/torch.h>

#include "mpm/materials/material.h"
#include "nn/model.h"
#include "rom/field_gradients.h"
#include "rom/fields/network_fields.h"
#include "rom/fields/sources.h"

namespace nsf {

namespace {

class CromStress final : public PointFieldSource {
 public:
  explicit CromStress(const FieldContext& c) : c_(c) { set_points(); }
  std::string describe() const override { return "tau from dg/dX through the material (CROM)"; }
  void set_points() override { Xn_ = normalised_points(c_.fields.model(), c_.points); }
  void evaluate(const std::vector<uint32_t>& ids, const LatentPair& s, bool,
                std::vector<Mat3>& tau) override {
    const int64_t m = int64_t(ids.size());
    const torch::Tensor F =
        deformation_gradients(c_.fields.model(), Xn_.index_select(0, index_tensor(ids)),
                              latent_row(s.z).expand({m, s.z.size()}));
    const double* f = F.data_ptr<double>();
    tau.resize(ids.size());
    for (int64_t k = 0; k < m; ++k) {
      Mat3 Fk = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(f + 9 * k);
      MaterialPoint mp = c_.points.mat0[ids[k]];
      tau[k] = c_.materials[c_.points.material[ids[k]]]->update(Fk, mp, c_.dt);
    }
  }

 private:
  const FieldContext& c_;
  torch::Tensor Xn_;
};

}  // namespace

std::unique_ptr<PointFieldSource> make_crom_stress(const FieldContext& c) {
  return std::make_unique<CromStress>(c);
}

}  // namespace nsf
