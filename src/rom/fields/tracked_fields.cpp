// τ, C and v from each particle's own tracked state (rom/step/tracked_particles.h), as full order
// has them: τ and C an ablation of h and l that says how much of the ROM's error is theirs; v each
// point's own G2P velocity of the step before, in place of g's backward difference.
#include "core/error.h"
#include "rom/fields/sources.h"
#include "rom/step/tracked_particles.h"

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

// A point new to N (and every point at the first step) has no G2P velocity of its own yet: it
// takes g's backward difference.
class TrackedVelocity final : public VelocitySource {
 public:
  explicit TrackedVelocity(const FieldContext& c) : tracked_(*c.tracked), c_(c) {
    tracked_.enlist("--velocity tracked", false);
  }
  std::string describe() const override { return "v from each point's own G2P"; }
  void evaluate(const std::vector<uint32_t>& ids, const std::vector<Vec3>& x,
                const std::vector<Vec3>& x_prev, std::vector<Vec3>& v) override {
    v.resize(ids.size());
    for (size_t k = 0; k < ids.size(); ++k) {
      const Vec3* own = tracked_.last_velocity(ids[k]);
      v[k] = own ? *own : Vec3((x[k] - x_prev[k]) / c_.dt);
    }
  }

 private:
  TrackedParticles& tracked_;
  const FieldContext& c_;  // its Δt is the step's, which a split step shortens
};

}  // namespace

std::unique_ptr<PointFieldSource> make_tracked_stress(const FieldContext& c) {
  return std::make_unique<TrackedField>(c, true);
}
std::unique_ptr<PointFieldSource> make_tracked_affine(const FieldContext& c) {
  return std::make_unique<TrackedField>(c, false);
}

std::unique_ptr<VelocitySource> make_tracked_velocity(const FieldContext& c) {
  return std::make_unique<TrackedVelocity>(c);
}

}  // namespace nsf
