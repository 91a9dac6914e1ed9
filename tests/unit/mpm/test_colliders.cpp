// Rigid colliders, contact rules, scripted motion and domain walls (src/mpm/colliders).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "mpm/colliders/domain_walls.h"
#include "mpm/colliders/rigid_collider.h"

namespace nsf {
namespace {

using nlohmann::json;

std::unique_ptr<Collider> collider(const std::string& text) {
  return make_collider(json::parse(text), "colliders[0]");
}

Vec3 applied(const Collider& c, const Vec3& x, Vec3 v) {
  c.apply(x, v);
  return v;
}

void expect_vec(const Vec3& got, const Vec3& want) {
  EXPECT_TRUE((got - want).norm() < 1e-12)
      << "got " << got.transpose() << ", want " << want.transpose();
}

const char* kFloor = R"({"type": "plane", "point": [0, 0.1, 0], "normal": [0, 1, 0], )";

TEST(PlaneCollider, SlipRemovesApproachingNormalVelocityOnly) {
  auto c = collider(std::string(kFloor) + R"("contact": "slip"})");
  const Vec3 below(0.3, 0.05, 0.3), above(0.3, 0.15, 0.3);
  expect_vec(applied(*c, below, Vec3(1, -2, 0.5)), Vec3(1, 0, 0.5));
  expect_vec(applied(*c, below, Vec3(1, 2, 0.5)), Vec3(1, 2, 0.5));            // separating
  expect_vec(applied(*c, above, Vec3(1, -2, 0.5)), Vec3(1, -2, 0.5));          // not in contact
  expect_vec(applied(*c, Vec3(0.3, 0.1, 0.3), Vec3(0, -1, 0)), Vec3::Zero());  // on the surface
}

TEST(PlaneCollider, StickyStopsTheNode) {
  auto c = collider(std::string(kFloor) + R"("contact": "sticky"})");
  expect_vec(applied(*c, Vec3(0.3, 0.05, 0.3), Vec3(1, 2, 3)), Vec3::Zero());
}

TEST(PlaneCollider, FrictionSlowsOrStopsTheTangentialPart) {
  auto c = collider(std::string(kFloor) + R"("contact": "friction", "friction": 0.5})");
  const Vec3 x(0.3, 0.05, 0.3);
  // |v_t| = 1 > 0.5·|v_n|: slides, slowed by μ|v_n| = 0.5.
  expect_vec(applied(*c, x, Vec3(1, -1, 0)), Vec3(0.5, 0, 0));
  // |v_t| = 0.3 <= 0.5: static friction holds it.
  expect_vec(applied(*c, x, Vec3(0.3, -1, 0)), Vec3::Zero());
  // Separating nodes feel no friction.
  expect_vec(applied(*c, x, Vec3(1, 1, 0)), Vec3(1, 1, 0));
}

TEST(PlaneCollider, InclinedNormalIsNormalisedAndLeavesTangentialMotion) {
  auto c = collider(R"({"type": "plane", "point": [0.5, 0.5, 0.5], "normal": [1, 1, 0],
                        "contact": "slip"})");
  const Vec3 x(0.4, 0.4, 0.5);  // below the plane
  Vec3 v = applied(*c, x, Vec3(0, -1, 0));
  expect_vec(v, Vec3(0.5, -0.5, 0));  // slides down the slope
  EXPECT_NEAR(v.dot(Vec3(1, 1, 0).normalized()), 0.0, 1e-12);
  auto* rigid = dynamic_cast<RigidCollider*>(c.get());
  ASSERT_NE(rigid, nullptr);
  EXPECT_NEAR(rigid->signed_distance(x), -0.2 / std::sqrt(2.0), 1e-12);
  expect_vec(applied(*c, Vec3(0.6, 0.6, 0.5), Vec3(0, -1, 0)), Vec3(0, -1, 0));
}

TEST(BoxCollider, EachContactModeUsesTheNearestFaceNormal) {
  const std::string box = R"({"type": "box", "center": [0.5, 0.5, 0.5], "size": [0.2, 0.4, 0.2], )";
  const Vec3 near_px(0.59, 0.5, 0.5);  // inside, closest to the +x face
  auto slip = collider(box + R"("contact": "slip"})");
  expect_vec(applied(*slip, near_px, Vec3(-1, 0.5, 0)), Vec3(0, 0.5, 0));
  expect_vec(applied(*slip, Vec3(0.7, 0.5, 0.5), Vec3(-1, 0.5, 0)), Vec3(-1, 0.5, 0));
  auto sticky = collider(box + R"("contact": "sticky"})");
  expect_vec(applied(*sticky, near_px, Vec3(-1, 0.5, 0)), Vec3::Zero());
  auto fric = collider(box + R"("contact": "friction", "friction": 0.2})");
  expect_vec(applied(*fric, near_px, Vec3(-1, 0.5, 0)), Vec3(0, 0.3, 0));
}

TEST(BoxCollider, RotatedBoxTurnsItsFaces) {
  // A thin blade, 45° about z: its +y face normal becomes (-1, 1, 0)/√2.
  auto c = collider(R"({"type": "box", "center": [0.5, 0.5, 0.5], "size": [0.4, 0.02, 0.4],
                        "rotate_deg": [0, 0, 45], "contact": "slip"})");
  auto* rigid = dynamic_cast<RigidCollider*>(c.get());
  Vec3 n = Vec3(-1, 1, 0).normalized();
  Vec3 x = Vec3(0.5, 0.5, 0.5) + 0.005 * n;
  EXPECT_LT(rigid->signed_distance(x), 0.0);
  expect_vec(rigid->normal(x), n);
  expect_vec(applied(*c, x, -n + Vec3(0, 0, 1)), Vec3(0, 0, 1));
  EXPECT_GT(rigid->signed_distance(Vec3(0.5, 0.53, 0.5)), 0.0);
}

TEST(CylinderCollider, SideAndCapNormals) {
  auto c = collider(R"({"type": "cylinder", "center": [0.5, 0.5, 0.5], "radius": 0.1,
                        "height": 0.4, "axis": "y", "contact": "slip"})");
  expect_vec(applied(*c, Vec3(0.5, 0.5, 0.59), Vec3(0, 0.3, -1)), Vec3(0, 0.3, 0));   // side
  expect_vec(applied(*c, Vec3(0.5, 0.69, 0.5), Vec3(0.3, -1, 0)), Vec3(0.3, 0, 0));   // top cap
  expect_vec(applied(*c, Vec3(0.5, 0.75, 0.5), Vec3(0.3, -1, 0)), Vec3(0.3, -1, 0));  // outside
  auto sticky = collider(R"({"type": "cylinder", "center": [0.5, 0.5, 0.5], "radius": 0.1,
                             "height": 0.4, "axis": "x", "contact": "sticky"})");
  expect_vec(applied(*sticky, Vec3(0.65, 0.5, 0.5), Vec3(1, 1, 1)), Vec3::Zero());
  expect_vec(applied(*sticky, Vec3(0.5, 0.65, 0.5), Vec3(1, 1, 1)), Vec3(1, 1, 1));
  auto fric = collider(R"({"type": "cylinder", "center": [0.5, 0.5, 0.5], "radius": 0.1,
                           "height": 0.4, "contact": "friction", "friction": 1.0})");
  expect_vec(applied(*fric, Vec3(0.5, 0.5, 0.59), Vec3(0, 0.5, -1)), Vec3::Zero());
}

TEST(ColliderMotion, VelocityScriptMovesAndSpinsInItsWindow) {
  auto c = collider(R"({"type": "box", "center": [0.5, 0.5, 0.5], "size": [0.2, 0.2, 0.2],
                        "contact": "sticky",
                        "motion": {"velocity": [1, 0, 0], "angular_velocity": [0, 0, 2],
                                   "start": 0.1, "end": 0.3}})");
  auto* rigid = dynamic_cast<RigidCollider*>(c.get());
  c->set_time(0.05);  // before the window: at rest
  expect_vec(rigid->pose().center, Vec3(0.5, 0.5, 0.5));
  expect_vec(rigid->velocity_at(Vec3(0.5, 0.6, 0.5)), Vec3::Zero());

  c->set_time(0.2);
  const Vec3 center(0.6, 0.5, 0.5);
  expect_vec(rigid->pose().center, center);
  const Vec3 x = center + Vec3(0, 0.05, 0);
  // v_c = v + ω × (x − c) = (1,0,0) + (0,0,2) × (0,0.05,0) = (0.9, 0, 0).
  expect_vec(applied(*c, x, Vec3(5, 5, 5)), Vec3(0.9, 0, 0));
  // Turned by ω·(t − start) = 0.2 rad about z.
  EXPECT_NEAR(std::atan2(rigid->pose().rotation(1, 0), rigid->pose().rotation(0, 0)), 0.2, 1e-12);

  c->set_time(1.0);  // after the window: parked at the final pose
  expect_vec(rigid->pose().center, Vec3(0.7, 0.5, 0.5));
  expect_vec(applied(*c, Vec3(0.7, 0.5, 0.5), Vec3(5, 5, 5)), Vec3::Zero());
}

TEST(ColliderMotion, KeyframesInterpolateCentreAndRotation) {
  auto c = collider(R"({"type": "box", "center": [0.5, 0.8, 0.5], "size": [0.3, 0.02, 0.3],
                        "contact": "sticky",
                        "motion": {"keyframes": [
                           {"t": 0.0, "center": [0.5, 0.8, 0.5]},
                           {"t": 1.0, "center": [0.5, 0.4, 0.5], "rotate_deg": [0, 0, 90]}]}})");
  auto* rigid = dynamic_cast<RigidCollider*>(c.get());
  c->set_time(0.5);
  expect_vec(rigid->pose().center, Vec3(0.5, 0.6, 0.5));
  expect_vec(rigid->pose().velocity, Vec3(0, -0.4, 0));
  expect_vec(rigid->pose().angular_velocity, Vec3(0, 0, M_PI / 2));
  EXPECT_NEAR(std::atan2(rigid->pose().rotation(1, 0), rigid->pose().rotation(0, 0)), M_PI / 4,
              1e-12);
  c->set_time(2.0);
  expect_vec(rigid->pose().center, Vec3(0.5, 0.4, 0.5));
  expect_vec(rigid->pose().velocity, Vec3::Zero());
}

TEST(ColliderMotion, HostDrivenPoseReplacesTheScriptAndMovesOnWithItsVelocities) {
  auto c = collider(R"({"type": "box", "center": [0.5, 0.5, 0.5], "size": [0.2, 0.2, 0.2],
                        "contact": "sticky", "motion": {"velocity": [1, 0, 0]}})");
  auto* rigid = dynamic_cast<RigidCollider*>(c.get());
  EXPECT_FALSE(rigid->driven());
  RigidPose host;
  host.center = Vec3(0.4, 0.3, 0.5);
  host.velocity = Vec3(0, 2, 0);
  host.angular_velocity = Vec3(0, 0, 1);
  rigid->drive(host, 0.1);
  EXPECT_TRUE(rigid->driven());
  expect_vec(rigid->pose().center, host.center);  // now, not at the script's 0.6

  c->set_time(0.15);  // the next step: moved on by v·Δt and turned by ω·Δt, the script ignored
  expect_vec(rigid->pose().center, Vec3(0.4, 0.4, 0.5));
  EXPECT_NEAR(std::atan2(rigid->pose().rotation(1, 0), rigid->pose().rotation(0, 0)), 0.05, 1e-12);
  // The contact sees the host's velocities: v + ω × (x − c).
  expect_vec(applied(*c, Vec3(0.4, 0.45, 0.5), Vec3(5, 5, 5)), Vec3(-0.05, 2, 0));

  host.center = Vec3(0.2, 0.3, 0.5);  // the next frame: the host's pose again
  host.velocity = host.angular_velocity = Vec3::Zero();
  rigid->drive(host, 0.2);
  c->set_time(0.3);
  expect_vec(rigid->pose().center, host.center);
  expect_vec(applied(*c, Vec3(0.2, 0.3, 0.5), Vec3(5, 5, 5)), Vec3::Zero());
}

TEST(ColliderMotion, GripsPullingApartMoveOppositeWays) {
  const char* grip = R"({"type": "box", "center": [%g, 0.5, 0.5], "size": [0.1, 0.2, 0.2],
                         "contact": "sticky", "motion": {"velocity": [%g, 0, 0], "end": 1}})";
  char left[400], right[400];
  std::snprintf(left, sizeof left, grip, 0.3, -0.2);
  std::snprintf(right, sizeof right, grip, 0.7, 0.2);
  auto l = collider(left), r = collider(right);
  l->set_time(0.5);
  r->set_time(0.5);
  expect_vec(applied(*l, Vec3(0.2, 0.5, 0.5), Vec3::Zero()), Vec3(-0.2, 0, 0));
  expect_vec(applied(*r, Vec3(0.8, 0.5, 0.5), Vec3::Zero()), Vec3(0.2, 0, 0));
}

TEST(ColliderJson, RejectsBadCollidersNamingTheKey) {
  auto expect_error = [](const std::string& text, const std::string& needle) {
    try {
      collider(text);
      ADD_FAILURE() << "accepted " << text;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect_error(R"({"type": "cone"})", "colliders[0].type");
  expect_error(std::string(kFloor) + R"("contact": "glue"})", "colliders[0].contact");
  expect_error(std::string(kFloor) + R"("contact": "friction"})", "colliders[0].friction");
  expect_error(std::string(kFloor) + R"("contact": "slip", "friction": 0.3})",
               "colliders[0].friction");
  expect_error(std::string(kFloor) + R"("contact": "friction", "friction": -1})",
               "colliders[0].friction");
  expect_error(R"({"type": "plane", "point": [0, 0, 0], "normal": [0, 0, 0]})",
               "colliders[0].normal");
  expect_error(R"({"type": "box", "center": [0, 0, 0], "size": [1, 0, 1]})",
               "colliders[0].size[1]");
  expect_error(R"({"type": "box", "center": [0, 0, 0], "size": [1, 1, 1], "radius": 2})",
               "colliders[0].radius");
  expect_error(R"({"type": "box", "center": [0, 0, 0], "size": [1, 1, 1],
                   "motion": {"velocity": [1, 0, 0], "keyframes": [{"t": 0}]}})",
               "colliders[0].motion.velocity");
  expect_error(R"({"type": "box", "center": [0, 0, 0], "size": [1, 1, 1],
                   "motion": {"keyframes": [{"t": 1}, {"t": 1}]}})",
               "colliders[0].motion.keyframes[1].t");
  expect_error(R"({"type": "box", "center": [0, 0, 0], "size": [1, 1, 1],
                   "motion": {"start": 2, "end": 1}})",
               "colliders[0].motion.end");
}

SimSettings walls(Contact mode, double friction = 0.0) {
  SimSettings s;
  s.wall_contact = mode;
  s.wall_friction = friction;
  s.wall_nodes = 3;
  return s;
}

Vec3 walled(const SimSettings& s, int i, int j, int k, Vec3 v) {
  apply_domain_walls(s, i, j, k, Vec3i(10, 10, 10), v);
  return v;
}

TEST(DomainWalls, SlipStopsMotionIntoEachFace) {
  SimSettings s = walls(Contact::Slip);
  expect_vec(walled(s, 2, 5, 5, Vec3(-1, 1, 0)), Vec3(0, 1, 0));     // low-x wall
  expect_vec(walled(s, 2, 5, 5, Vec3(1, 1, 0)), Vec3(1, 1, 0));      // leaving it
  expect_vec(walled(s, 7, 5, 5, Vec3(1, 1, 0)), Vec3(0, 1, 0));      // high-x wall
  expect_vec(walled(s, 5, 0, 5, Vec3(1, -1, 0)), Vec3(1, 0, 0));     // floor
  expect_vec(walled(s, 5, 5, 9, Vec3(0, 0, 1)), Vec3::Zero());       // high-z wall
  expect_vec(walled(s, 0, 0, 5, Vec3(-1, -1, 1)), Vec3(0, 0, 1));    // corner: both walls
  expect_vec(walled(s, 3, 6, 6, Vec3(-1, 1, -1)), Vec3(-1, 1, -1));  // interior node
}

TEST(DomainWalls, StickyAndFriction) {
  expect_vec(walled(walls(Contact::Sticky), 5, 1, 5, Vec3(1, 1, 1)), Vec3::Zero());
  expect_vec(walled(walls(Contact::Sticky), 5, 3, 5, Vec3(1, 1, 1)), Vec3(1, 1, 1));
  SimSettings f = walls(Contact::Friction, 0.5);
  expect_vec(walled(f, 5, 1, 5, Vec3(2, -1, 0)), Vec3(1.5, 0, 0));
  expect_vec(walled(f, 5, 1, 5, Vec3(0.4, -1, 0)), Vec3::Zero());
}

}  // namespace
}  // namespace nsf
