// τ and C from each particle's own tracked state (rom/tracked_particles.h), as full order has
// them: an ablation of h and l that says how much of the ROM's error is theirs.
#include "core/error.h"
#include "rom/fields/sources.h"
#include "rom/tracked_particles.h"

namespace nsf {

namespace {

class TrackedField final : public PointFieldSource {
 public:
  TrackedField(const FieldContext& c, bool stress) : tracked_(*c.tracked), stress_(stress) {
    tracked_.enlist(stress ? "--stress tracked" : "--affine tracked", stress);
  }
  std::string describe() const override {
    return stress_ ? "tau tracked per particle" : "C tracked per particle";
  }
  void set_points() override {}
  void evaluate(const std::vector<uint32_t>& ids, const LatentPair&, bool,
                std::vector<Mat3>& out) override {
    out.resize(ids.size());
    for (size_t k = 0; k < ids.size(); ++k)
      out[k] = stress_ ? tracked_.tau(ids[k]) : tracked_.C(ids[k]);
  }

 private:
  TrackedParticles& tracked_;
  bool stress_;
};

}  // namespace

std::unique_ptr<PointFieldSource> make_tracked_stress(const FieldContext& c) {
  return std::make_unique<TrackedField>(c, true);
}
std::unique_ptr<PointFieldSource> make_tracked_affine(const FieldContext& c) {
  return std::make_unique<TrackedField>(c, false);
}

}  // namespace nsf
