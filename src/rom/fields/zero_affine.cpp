// C = 0: no affine field (the CROM baseline's default).
#include "rom/fields/sources.h"

namespace nsf {

namespace {

class ZeroAffine final : public PointFieldSource {
 public:
  std::string describe() const override { return "C = 0"; }
  void evaluate(const std::vector<uint32_t>& ids, const LatentPair&, bool,
                std::vector<Mat3>& C) override {
    C.assign(ids.size(), Mat3::Zero());
  }
};

}  // namespace

std::unique_ptr<PointFieldSource> make_zero_affine(const FieldContext&) {
  return std::make_unique<ZeroAffine>();
}

}  // namespace nsf
