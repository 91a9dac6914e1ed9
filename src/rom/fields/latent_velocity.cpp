// v = (g(X, ẑ_n) − g(X, ẑ_{n−1})) / Δt on N: the paper's velocities, a backward difference of the
// deformation field across one ROM step.
#include "rom/fields/sources.h"

namespace nsf {

namespace {

class LatentVelocity final : public VelocitySource {
 public:
  explicit LatentVelocity(const FieldContext& c) : c_(c) {}
  std::string describe() const override { return ""; }
  void evaluate(const std::vector<uint32_t>& ids, const std::vector<Vec3>& x,
                const std::vector<Vec3>& x_prev, std::vector<Vec3>& v) override {
    v.resize(ids.size());
    for (size_t k = 0; k < ids.size(); ++k) v[k] = (x[k] - x_prev[k]) / c_.dt;
  }

 private:
  const FieldContext& c_;  // its Δt is the step's, which a split step shortens
};

}  // namespace

std::unique_ptr<VelocitySource> make_latent_velocity(const FieldContext& c) {
  return std::make_unique<LatentVelocity>(c);
}

}  // namespace nsf
