// Sweeps that vary several things at once (issue #55 item 4): the Latin hypercube and Sobol
// designs, the "vary" axes and random collider paths of a scene's sweep, and the training box a
// run records and a model keeps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <set>

#include "core/error.h"
#include "core/rotation.h"
#include "data/design.h"
#include "data/perturbation_spec.h"
#include "data/sweep_spec.h"
#include "data/training_box.h"
#include "error_matchers.h"
#include "mpm/colliders/rigid_collider.h"
#include "mpm/scene/scene.h"

using nlohmann::json;

namespace {

// Every interval [k/n, (k+1)/n) of every axis holds exactly one of the n points.
void expect_stratified(const std::vector<double>& u, int n, int d) {
  ASSERT_EQ(u.size(), size_t(n) * size_t(d));
  for (int k = 0; k < d; ++k) {
    std::set<int> cells;
    for (int i = 0; i < n; ++i) {
      const double x = u[size_t(i * d + k)];
      ASSERT_GE(x, 0.0);
      ASSERT_LT(x, 1.0);
      cells.insert(int(x * n));
    }
    EXPECT_EQ(cells.size(), size_t(n)) << "axis " << k;
  }
}

TEST(SweepDesign, ALatinHypercubeHasOnePointInEachIntervalOfEachAxisAndFollowsItsSeed) {
  for (int n : {1, 2, 7, 40}) expect_stratified(nsf::latin_hypercube(n, 4, 3), n, 4);
  EXPECT_EQ(nsf::latin_hypercube(12, 3, 5), nsf::latin_hypercube(12, 3, 5));
  EXPECT_NE(nsf::latin_hypercube(12, 3, 5), nsf::latin_hypercube(12, 3, 6));
  EXPECT_THROW(nsf::latin_hypercube(0, 2, 1), nsf::Error);
}

TEST(SweepDesign, SobolPointsAreStratifiedInEveryAxisAndLaterOnesFillTheGaps) {
  const int d = nsf::kSobolMaxDimensions;
  // The first 2^m points (the origin included, shifted) fill every interval of 2^-m.
  for (int m : {1, 3, 5}) expect_stratified(nsf::sobol_points(0, 1 << m, d, 9), 1 << m, d);
  // Without its shift: the sequence's known start in two dimensions.
  const std::vector<double> first = nsf::sobol_points(1, 3, 2, 0);
  std::mt19937_64 rng(0);
  const double sx = double(uint32_t(rng() >> 32)) * 0x1.0p-32,
               sy = double(uint32_t(rng() >> 32)) * 0x1.0p-32;
  const auto unshift = [](double v, double s) {
    return double(uint32_t(v * 0x1.0p32) ^ uint32_t(s * 0x1.0p32)) * 0x1.0p-32;
  };
  // Gray-code order: points 1, 2, 3 are (1/2, 1/2), (3/4, 1/4), (1/4, 3/4).
  EXPECT_DOUBLE_EQ(unshift(first[0], sx), 0.5);
  EXPECT_DOUBLE_EQ(unshift(first[1], sy), 0.5);
  EXPECT_DOUBLE_EQ(unshift(first[2], sx), 0.75);
  EXPECT_DOUBLE_EQ(unshift(first[3], sy), 0.25);
  EXPECT_DOUBLE_EQ(unshift(first[4], sx), 0.25);
  EXPECT_DOUBLE_EQ(unshift(first[5], sy), 0.75);
  // Points 8 … 15 are the other halves of the cells points 0 … 7 hold in each axis.
  std::vector<double> all = nsf::sobol_points(0, 8, d, 4);
  const std::vector<double> more = nsf::sobol_points(8, 8, d, 4);
  all.insert(all.end(), more.begin(), more.end());
  expect_stratified(all, 16, d);
  EXPECT_THROW(nsf::sobol_points(0, 4, d + 1, 1), nsf::Error);
}

TEST(SweepDesign, EulerAnglesReadBackFromTheirRotation) {
  for (const nsf::Vec3& deg : {nsf::Vec3(10, -20, 30), nsf::Vec3(0, 0, 0), nsf::Vec3(-170, 45, 90),
                               nsf::Vec3(30, 90, 0), nsf::Vec3(0, -90, 60)}) {
    const nsf::Mat3 R = nsf::rotation_from_euler_deg(deg);
    EXPECT_LT((nsf::rotation_from_euler_deg(nsf::euler_deg_from_rotation(R)) - R).norm(), 1e-9)
        << deg.transpose();
  }
}

// Two plates squeeze a block; the sweep varies its stiffness, the squeeze's depth, and lets the
// left plate wander.
json plates_scene() {
  return json::parse(R"({
    "name": "plates",
    "simulation": { "dx": 0.0625, "dt": 2e-3, "frames": 10, "substeps": 5, "ppc": 2 },
    "objects": [ { "shape": { "type": "box", "min": [0.375, 0.25, 0.375], "max": [0.625, 0.45, 0.625] },
                   "material": { "type": "fixed_corotated", "E": 1000, "nu": 0.3 } } ],
    "colliders": [
      { "type": "plane", "point": [0, 0.25, 0], "normal": [0, 1, 0], "contact": "sticky" },
      { "type": "box", "center": [0.3, 0.35, 0.5], "size": [0.05, 0.3, 0.3],
        "motion": { "keyframes": [ { "t": 0, "center": [0.3, 0.35, 0.5] },
                                   { "t": 0.1, "center": [0.36, 0.35, 0.5] } ] } } ],
    "sweep": { "parameter": "stiffness", "set": ["material.E={mu*1000}"], "range": [1, 3],
               "train": 8, "test": 3, "seed": 7,
               "vary": [ { "name": "depth", "range": [0.34, 0.38],
                           "set": ["colliders[1].motion.keyframes[1].center=[{v},0.35,0.5]"] } ],
               "paths": [ { "name": "left plate wanders", "collider": 1, "start": 0.02,
                            "end": 0.09, "offset": [0.01, 0.02, 0.0], "max_speed": 2.0 } ] }
  })");
}

nsf::SweepSpec parsed(const json& scene) {
  return nsf::parse_sweep(scene.at("sweep"), scene);
}

TEST(SweepSpec, AHypercubeSweepPlacesItsRunsOverMuAndEveryAxis) {
  const nsf::SweepSpec s = parsed(plates_scene());
  ASSERT_EQ(s.vary.size(), 1u);
  ASSERT_EQ(s.paths.size(), 1u);
  EXPECT_EQ(s.design, nsf::SweepDesign::lhs);  // the default with axes
  const std::vector<nsf::SweepRun> runs = nsf::plan_sweep(s);
  ASSERT_EQ(runs.size(), 11u);
  std::set<int> mu_cells, depth_cells;
  std::set<uint64_t> seeds;
  for (const nsf::SweepRun& r : runs) {
    ASSERT_EQ(r.values.size(), 1u);
    EXPECT_GE(r.mu, 1.0);
    EXPECT_LT(r.mu, 3.0);
    EXPECT_GE(r.values[0], 0.34);
    EXPECT_LT(r.values[0], 0.38);
    seeds.insert(r.path_seed);
    if (r.split == "train") {
      mu_cells.insert(int((r.mu - 1) / 2 * 8));
      depth_cells.insert(int((r.values[0] - 0.34) / 0.04 * 8));
    }
  }
  EXPECT_EQ(mu_cells.size(), 8u);
  EXPECT_EQ(depth_cells.size(), 8u);
  EXPECT_EQ(seeds.size(), runs.size());  // every run its own path
  // The same plan from the same scene; another seed, another plan.
  const std::vector<nsf::SweepRun> again = nsf::plan_sweep(parsed(plates_scene()));
  for (size_t i = 0; i < runs.size(); ++i) {
    EXPECT_EQ(runs[i].mu, again[i].mu);
    EXPECT_EQ(runs[i].values, again[i].values);
    EXPECT_EQ(runs[i].path_seed, again[i].path_seed);
  }
  json other = plates_scene();
  other["sweep"]["seed"] = 8;
  EXPECT_NE(nsf::plan_sweep(parsed(other))[0].mu, runs[0].mu);
  other["sweep"]["design"] = "sobol";
  EXPECT_EQ(nsf::plan_sweep(parsed(other)).size(), 11u);
}

TEST(SweepSpec, ARunsSceneHasItsValuesAndASmoothPathWithinItsLimits) {
  const json base = plates_scene();
  const nsf::SweepSpec s = parsed(base);
  const nsf::SweepRun run = nsf::plan_sweep(s)[2];
  json scene = base;
  scene.erase("sweep");
  nsf::apply_sweep_run(s, run, scene);
  EXPECT_DOUBLE_EQ(scene["objects"][0]["material"]["E"].get<double>(), run.mu * 1000);
  nsf::Scene built = nsf::build_scene(scene);
  auto* plate = dynamic_cast<nsf::RigidCollider*>(built.colliders[1].get());
  ASSERT_NE(plate, nullptr);
  // The script without the path: the plate slides from 0.3 to the run's depth by t = 0.1.
  double widest = 0, fastest = 0;
  const double frame = 0.01;
  nsf::Vec3 last = nsf::Vec3::Zero();
  for (int f = 0; f <= 10; ++f) {
    const double t = f * frame;
    plate->set_time(t);
    const nsf::Vec3 c = plate->pose().center;
    const double scripted_x = 0.3 + (run.values[0] - 0.3) * std::min(t / 0.1, 1.0);
    const nsf::Vec3 off = c - nsf::Vec3(scripted_x, 0.35, 0.5);
    if (t <= 0.02 + 1e-12 || t >= 0.09 - 1e-12) {
      EXPECT_LT(off.norm(), 1e-12) << "t = " << t;
    }
    EXPECT_LE(std::abs(off.x()), 0.01 + 1e-12);
    EXPECT_LE(std::abs(off.y()), 0.02 + 1e-12);
    EXPECT_EQ(off.z(), 0.0);
    widest = std::max(widest, std::max(std::abs(off.x()) / 0.01, std::abs(off.y()) / 0.02));
    if (f > 0) fastest = std::max(fastest, (c - last).norm() / frame);
    last = c;
  }
  EXPECT_GT(widest, 0.3);  // it does wander (at least half its reach, sampled at frames)
  EXPECT_LE(fastest, 2.0 + 1e-9);
  // A tighter speed limit shrinks the path, down to the script's own speed.
  json slow = base;
  slow["sweep"]["paths"][0]["max_speed"] = 0.8;
  const nsf::SweepSpec ss = parsed(slow);
  json scene2 = slow;
  scene2.erase("sweep");
  nsf::apply_sweep_run(ss, nsf::plan_sweep(ss)[2], scene2);
  nsf::Scene built2 = nsf::build_scene(scene2);
  auto* p2 = dynamic_cast<nsf::RigidCollider*>(built2.colliders[1].get());
  for (int f = 1; f <= 10; ++f) {
    p2->set_time((f - 1) * frame);
    const nsf::Vec3 a = p2->pose().center;
    p2->set_time(f * frame);
    EXPECT_LE((p2->pose().center - a).norm() / frame, 0.8 + 1e-9) << "frame " << f;
  }
}

TEST(SweepSpec, AMultiAxisSweepRefusesWhatItCannotRunNamingTheKey) {
  const auto refused = [](const std::function<void(json&)>& edit, const std::string& words) {
    json scene = plates_scene();
    edit(scene);
    nsf::testing::expect_error([&] { parsed(scene); }, {words});
  };
  refused([](json& s) { s["sweep"]["design"] = "grid"; }, "needs \"lhs\" or \"sobol\"");
  refused([](json& s) { s["sweep"]["design"] = "random"; }, "sweep.design");
  refused([](json& s) { s["sweep"]["vary"].push_back(s["sweep"]["vary"][0]); }, "already an axis");
  refused([](json& s) { s["sweep"]["vary"][0]["name"] = "stiffness"; }, "the sweep's parameter");
  refused([](json& s) { s["sweep"]["vary"][0]["set"] = {"material.E={v}"}; },
          "overwrites what mu sets");
  refused([](json& s) { s["sweep"]["vary"][0]["set"] = {"colliders[0].point=[0,0.25,0]"}; },
          "leaves the scene unchanged");
  // An axis that starts from the scene's own value (a throw from rest) changes it at its other
  // end, and is taken; one the scene already holds at both ends is not.
  json from_rest = plates_scene();
  from_rest["objects"][0]["velocity"] = {0, 0, 0};
  from_rest["sweep"]["vary"].push_back(
      {{"name", "thrown down"}, {"range", {0, 0.4}}, {"set", {"objects[0].velocity[1]={v*-1}"}}});
  EXPECT_EQ(parsed(from_rest).vary.size(), 2u);
  refused(
      [](json& s) {
        s["objects"][0]["velocity"] = {0, 0, 0};
        s["sweep"]["vary"].push_back({{"name", "thrown down"},
                                      {"range", {0, 0.4}},
                                      {"set", {"objects[0].velocity[1]={v*0}"}}});
      },
      "and at its other end");
  // Axes apply in order: one may set a part of what an earlier axis made (a throw's second
  // component after the first axis set the velocity, which the scene does not have), and is run
  // that way; one that overwrites an earlier axis is refused.
  json throws = plates_scene();
  throws["objects"][0].erase("velocity");
  throws["sweep"]["vary"].push_back({{"name", "thrown along x"},
                                     {"range", {-0.2, 0.2}},
                                     {"set", {"objects[0].velocity=[{v},0,0]"}}});
  throws["sweep"]["vary"].push_back({{"name", "thrown along z"},
                                     {"range", {-0.1, 0.1}},
                                     {"set", {"objects[0].velocity[2]={v}"}}});
  const nsf::SweepSpec ts = parsed(throws);
  ASSERT_EQ(ts.vary.size(), 3u);
  const nsf::SweepRun tr = nsf::plan_sweep(ts)[1];
  json thrown = throws;
  thrown.erase("sweep");
  nsf::apply_sweep_run(ts, tr, thrown);
  EXPECT_EQ(thrown["objects"][0]["velocity"], json({tr.values[1], 0, tr.values[2]}));
  json overwritten = throws;
  overwritten["sweep"]["vary"][2]["set"] = {"objects[0].velocity=[0,0,{v}]"};
  nsf::testing::expect_error([&] { parsed(overwritten); },
                             {"overwrites what 'thrown along x' sets"});
  refused([](json& s) { s["sweep"]["vary"][0]["set"] = {"objects[0].shape.max[0]={v}"}; },
          "changes the particles");
  refused([](json& s) { s["sweep"]["paths"][0]["collider"] = 5; }, "sweep.paths[0].collider");
  refused([](json& s) { s["sweep"]["paths"][0]["end"] = 0.5; }, "start < end");
  refused([](json& s) { s["sweep"]["paths"][0]["offset"] = {0, 0, 0}; }, "not all 0");
  refused([](json& s) { s["sweep"]["paths"][0]["max_speed"] = 0.3; }, "faster than max_speed");
  refused([](json& s) { s["sweep"]["paths"][0]["speed"] = 1; }, "speed");
}

// `nsf generalize` draws the sweep's other axes too, from a stream of their own: a scene whose
// sweep gains axes keeps its draws' v and μ, so its benchmark rows stay comparable.
TEST(SweepSpec, BenchmarkDrawsSetTheAxesAndKeepTheirValuesAndMuWithoutThem) {
  json scene = plates_scene();
  scene["generalize"] = json::parse(R"({"perturbations": [
      {"name": "plate higher", "range": [0.36, 0.4],
       "set": ["colliders[1].motion.keyframes[1].center=[0.35,{v},0.5]"]}]})");
  const nsf::SweepSpec with = parsed(scene);
  json plain = scene;
  plain["sweep"].erase("vary");
  const nsf::SweepSpec without = parsed(plain);
  const nsf::GeneralizeSpec g = nsf::parse_generalize(scene["generalize"], scene, &with);
  const auto a = nsf::plan_draws(g, &with, 6, 3), b = nsf::plan_draws(g, &without, 6, 3);
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].value, b[i].value);
    EXPECT_EQ(a[i].mu, b[i].mu);
    ASSERT_EQ(a[i].values.size(), 1u);
    EXPECT_TRUE(b[i].values.empty());
    EXPECT_GE(a[i].values[0], 0.34);
    EXPECT_LT(a[i].values[0], 0.38);
  }
}

TEST(TrainingBox, GrowsOverRunsReadsBackAndSaysWhatLiesOutside) {
  nsf::TrainingBox a, b;
  a.parameters = {{"stiffness", 1, 1}};
  a.colliders = {{1, nsf::Vec3(0.3, 0.2, 0.5), nsf::Vec3(0.35, 0.2, 0.5), 0.5, 0}};
  b.parameters = {{"stiffness", 2, 2}, {"depth", 0.36, 0.36}};
  b.colliders = {{1, nsf::Vec3(0.3, 0.18, 0.5), nsf::Vec3(0.37, 0.2, 0.5), 0.7, 0}};
  a.include(b);
  ASSERT_EQ(a.parameters.size(), 2u);
  EXPECT_EQ(a.parameters[0].lo, 1);
  EXPECT_EQ(a.parameters[0].hi, 2);
  EXPECT_EQ(a.colliders[0].hi.x(), 0.37);
  EXPECT_EQ(a.colliders[0].lo.y(), 0.18);
  EXPECT_EQ(a.colliders[0].max_speed, 0.7);
  const nsf::TrainingBox c = nsf::TrainingBox::from_json(a.to_json(), "test");
  EXPECT_EQ(c.to_json(), a.to_json());
  // Inside, within a cell, beyond it, and too fast.
  EXPECT_EQ(a.collider_outside(1, nsf::Vec3(0.33, 0.19, 0.5), 0.6, 0.01), "");
  EXPECT_EQ(a.collider_outside(1, nsf::Vec3(0.375, 0.19, 0.5), 0.6, 0.01), "");
  const std::string out = a.collider_outside(1, nsf::Vec3(0.33, 0.19, 0.45), 0.6, 0.01);
  EXPECT_NE(out.find("beyond its training box in z"), std::string::npos) << out;
  EXPECT_NE(a.collider_outside(1, nsf::Vec3(0.33, 0.19, 0.5), 1.0, 0.01).find("faster"),
            std::string::npos);
  EXPECT_EQ(a.collider_outside(0, nsf::Vec3(9, 9, 9), 9, 0.01), "");  // not in the box
  for (const char* bad : {R"([])", R"({"parameters": 3})", R"({"parameters": [{"name": "a"}]})",
                          R"({"colliders": [{"collider": 0, "lo": [0,0], "hi": [0,0,0],
                              "max_speed": 0, "max_angular_speed": 0}]})",
                          R"({"colliders": [{"collider": 0, "lo": [1,0,0], "hi": [0,0,0],
                              "max_speed": 0, "max_angular_speed": 0}]})"})
    EXPECT_THROW(nsf::TrainingBox::from_json(json::parse(bad), "test"), nsf::Error) << bad;
}

}  // namespace
