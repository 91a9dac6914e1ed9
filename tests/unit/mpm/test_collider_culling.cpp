// The grid update asks a collider only on the blocks of nodes it may reach (Collider::may_touch):
// the grid velocities and the particles must come out bit for bit as when every collider is
// applied to every node, whether the body touches the colliders or not.
#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <nlohmann/json.hpp>
#include <random>

#include "engine_fixtures.h"
#include "mpm/colliders/rigid_collider.h"
#include "mpm/simulation.h"

namespace nsf {
namespace {

using nlohmann::json;

// Forwards to a real collider, counts apply() calls, and with `cull` false answers may_touch
// with the base class's "always", which restores the pass over every node.
class Forwarding final : public Collider {
 public:
  Forwarding(std::unique_ptr<Collider> inner, bool cull) : inner_(std::move(inner)), cull_(cull) {}
  std::string type() const override { return inner_->type(); }
  void set_time(double t) override { inner_->set_time(t); }
  void apply(const Vec3& x, Vec3& v) const override {
    calls_.fetch_add(1, std::memory_order_relaxed);
    inner_->apply(x, v);
  }
  bool may_touch(const Vec3& x, double radius) const override {
    return cull_ ? inner_->may_touch(x, radius) : Collider::may_touch(x, radius);
  }
  long calls() const { return calls_.load(); }

 private:
  std::unique_ptr<Collider> inner_;
  bool cull_;
  mutable std::atomic<long> calls_{0};
};

// A falling, sideways-moving block of jelly and the given colliders (JSON texts).
Scene scene_with(const std::vector<std::string>& colliders, bool cull) {
  Scene s =
      testing::box_scene(Vec3(0.35, 0.3, 0.35), Vec3(0.6, 0.5, 0.6), 0.05, 1e-3, 5e3, 0.3, 1000);
  for (size_t p = 0; p < s.particles.size(); ++p) s.particles.v[p] = Vec3(0.8, -1.0, 0.2);
  for (const std::string& text : colliders)
    s.colliders.push_back(
        std::make_unique<Forwarding>(make_collider(json::parse(text), "colliders[0]"), cull));
  return s;
}

long apply_calls(Simulation& sim) {
  long calls = 0;
  for (const auto& c : sim.colliders()) calls += static_cast<const Forwarding&>(*c).calls();
  return calls;
}

// Steps both and compares the grid and the particles bitwise after every step; returns the
// apply() calls of the culled run and of the full pass.
std::pair<long, long> compare_runs(const std::vector<std::string>& colliders, int steps) {
  Simulation culled(scene_with(colliders, true)), full(scene_with(colliders, false));
  for (int n = 0; n < steps; ++n) {
    culled.step();
    full.step();
    const Grid &a = culled.grid(), &b = full.grid();
    EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.node_count() * sizeof(GridNode)))
        << "grid differs after step " << n + 1;
    const Particles &p = culled.particles(), &q = full.particles();
    EXPECT_EQ(0, std::memcmp(p.x.data(), q.x.data(), p.size() * sizeof(Vec3)));
    EXPECT_EQ(0, std::memcmp(p.v.data(), q.v.data(), p.size() * sizeof(Vec3)));
    EXPECT_EQ(0, std::memcmp(p.C.data(), q.C.data(), p.size() * sizeof(Mat3)));
  }
  return {apply_calls(culled), apply_calls(full)};
}

TEST(ColliderCulling, BodyTouchingTheCollidersGivesTheFullPassBitForBit) {
  // A floor the block falls onto, a rotated box pushing into its side, a cylinder it runs into.
  const std::vector<std::string> colliders = {
      R"({"type": "plane", "point": [0, 0.28, 0], "normal": [0, 1, 0.1],
          "contact": "friction", "friction": 0.3})",
      R"({"type": "box", "center": [0.3, 0.4, 0.45], "size": [0.1, 0.3, 0.2],
          "rotate_deg": [0, 0, 20], "contact": "slip",
          "motion": {"velocity": [1.0, 0, 0], "start": 0, "end": 1}})",
      R"({"type": "cylinder", "center": [0.66, 0.4, 0.5], "radius": 0.05, "height": 0.3,
          "axis": "y", "contact": "sticky"})"};
  const auto [culled, full] = compare_runs(colliders, 30);
  EXPECT_GT(culled, 0);     // the colliders did act
  EXPECT_LT(culled, full);  // and the blocks out of their reach were skipped
}

TEST(ColliderCulling, BodyFarFromTheCollidersSkipsThemEverywhere) {
  const std::vector<std::string> colliders = {
      R"({"type": "box", "center": [0.1, 0.85, 0.1], "size": [0.05, 0.05, 0.05],
          "contact": "sticky"})",
      R"({"type": "plane", "point": [0, 0.05, 0], "normal": [0, 1, 0], "contact": "slip"})"};
  const auto [culled, full] = compare_runs(colliders, 10);
  EXPECT_EQ(culled, 0);
  EXPECT_GT(full, 0);
}

TEST(ColliderCulling, MayTouchIsFalseOnlyWhereNoPointWithinTheRadiusIsInContact) {
  const std::vector<std::string> texts = {
      R"({"type": "box", "center": [0.5, 0.5, 0.5], "size": [0.2, 0.1, 0.3],
          "rotate_deg": [10, 30, 45]})",
      R"({"type": "cylinder", "center": [0.5, 0.5, 0.5], "radius": 0.1, "height": 0.2,
          "axis": "z", "rotate_deg": [0, 40, 0]})",
      R"({"type": "plane", "point": [0.5, 0.5, 0.5], "normal": [1, 2, 3]})"};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const std::string& text : texts) {
    const auto c = make_collider(json::parse(text), "colliders[0]");
    const auto& rigid = static_cast<const RigidCollider&>(*c);
    int skipped = 0, kept = 0;
    for (int trial = 0; trial < 2000; ++trial) {
      const Vec3 centre(u(rng), u(rng), u(rng));
      const double radius = 0.2 * u(rng);
      if (c->may_touch(centre, radius)) {
        ++kept;
        continue;
      }
      ++skipped;
      for (int s = 0; s < 50; ++s) {
        Vec3 d(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
        const Vec3 x = centre + radius * u(rng) * d.normalized();
        ASSERT_GT(rigid.signed_distance(x), 0.0) << text << " skipped a point in contact";
      }
    }
    EXPECT_GT(skipped, 100) << text;
    EXPECT_GT(kept, 100) << text;
  }
}

}  // namespace
}  // namespace nsf
