// C from the ROM's own velocity field v = (g(·, ẑ_n) − g(·, ẑ_{n−1}))/Δt: APIC's C is the velocity
// gradient at the point, Ḟ F⁻¹ with F = ∂g/∂X (rom/field_gradients.h).
#include <torch/torch.h>

#include "nn/model.h"
#include "rom/field_gradients.h"
#include "rom/fields/network_fields.h"
#include "rom/fields/sources.h"

namespace nsf {

namespace {

class VelocityAffine final : public PointFieldSource {
 public:
  explicit VelocityAffine(const FieldContext& c) : c_(c) { set_points(); }
  std::string describe() const override { return "C from the gradient of g's velocity"; }
  void set_points() override { Xn_ = normalised_points(c_.fields.model(), c_.points); }
  void evaluate(const std::vector<uint32_t>& ids, const LatentPair& s, bool,
                std::vector<Mat3>& C) override {
    const int64_t m = int64_t(ids.size());
    const torch::Tensor Xn = Xn_.index_select(0, index_tensor(ids));
    NeuralModel& model = c_.fields.model();
    const torch::Tensor F =
        deformation_gradients(model, Xn, latent_row(s.z).expand({m, s.z.size()}));
    const torch::Tensor F_prev =
        deformation_gradients(model, Xn, latent_row(s.z_prev).expand({m, s.z_prev.size()}));
    velocity_gradients(F, F_prev, c_.dt, C);
  }

 private:
  const FieldContext& c_;
  torch::Tensor Xn_;
};

}  // namespace

std::unique_ptr<PointFieldSource> make_velocity_affine(const FieldContext& c) {
  return std::make_unique<VelocityAffine>(c);
}

}  // namespace nsf
