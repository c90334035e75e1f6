// What every backend must do, as a GoogleTest suite over backend names: the project runs it for
// every backend it has (test_contract.cpp), and code that registers its own backend runs it for
// that one. Installed as <chainmail/testing/backend_contract.hpp>. Include it in exactly one
// source file of a test program (it defines the tests), then, in namespace chainmail::test:
//
//   INSTANTIATE_TEST_SUITE_P(Mine, BackendContract, ::testing::Values(std::string("mine")),
//                            backend_param_name);
//
// The scenes are small and take seconds in every backend; where a test needs a settled state its
// scene sets the project's backends' knobs, and any other backend runs at its own defaults. A
// backend not built into the binary is skipped, saying so. The tests of one backend's own
// behaviour are in test_<backend>.cpp.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "backend_sim.hpp"
#include "collider_cases.hpp"

namespace chainmail::test {

using json = nlohmann::json;

inline constexpr double kGravity = 9.81;  // m/s^2, the scene default

class BackendContract : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override { skip_unless_built(GetParam()); }
  BackendSim sim(const json& document) const { return BackendSim(GetParam(), document); }
};

// one ring of the default geometry lying in the xz plane at `centre`
inline json lone_ring(const json& centre) {
  return {{"name", "lone_ring"},
          {"weave",
           {{"type", "4in1"}, {"rows", 1}, {"cols", 1}, {"plane", "xz"}, {"center", centre}}},
          {"duration", 1.0}};
}

// a small 4-in-1 sheet in the `plane`, rows x cols rings
inline json sheet(int rows, int cols, const std::string& plane) {
  return {{"name", "sheet"},
          {"weave", {{"type", "4in1"}, {"rows", rows}, {"cols", cols}, {"plane", plane}}},
          {"duration", 1.0}};
}

TEST_P(BackendContract, FirstFrameIsTheRestLayout) {
  auto run = sim(sheet(3, 3, "xy"));
  EXPECT_EQ(run.frame.t, 0.0);
  ASSERT_EQ(run.frame.size(), run.weave.size());
  // rigid backends scale lengths internally: equal up to that round trip (a ring is millimetres)
  EXPECT_LT((run.frame.position - run.weave.rest_position).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_EQ(run.frame.velocity.cwiseAbs().maxCoeff(), 0.0);
  for (int ring = 0; ring < run.frame.size(); ++ring) {
    EXPECT_NEAR(run.frame.orientation.col(ring).norm(), 1.0, 1e-12) << "ring " << ring;
  }
}

TEST_P(BackendContract, RestsOnEveryColliderType) {
  const double top = 0.01;  // m, collider top surface height
  for (const json& collider : colliders_with_top_at(top)) {
    json document = lone_ring({0.0, top + 0.01, 0.0});
    document["colliders"] = {collider};
    auto run = sim(document);
    run.advance(0.6);
    expect_ring_resting_on(run.frame, run.profile(), top, collider);
  }
}

TEST_P(BackendContract, FallsFreelyUnderGravity) {
  auto run = sim(lone_ring({0.1, 1.0, -0.2}));
  const Vec3 start = run.frame.position.col(0);
  const Quat attitude = run.frame.quat(0);
  const double t = 0.2;  // s
  run.advance(t);
  ASSERT_NEAR(run.frame.t, t, 1e-9);
  const double drop = start.y() - run.frame.position(1, 0);
  const double free_drop = 0.5 * kGravity * t * t;
  // semi-implicit Euler leads the parabola by g t h / 2 for an internal step h <= dt
  EXPECT_LT(drop, free_drop + kGravity * t * run.dt());
  // default drag only slows the fall: the strongest (plausible 5/s, massspring 0.2 % per step at
  // 2700 steps/s, about 5.4/s) keeps about 72 % of the free drop over 0.2 s
  EXPECT_GT(drop, 0.5 * free_drop);
  // no sideways drift (a micrometre, far below the wire radius) and no spin without a torque
  EXPECT_NEAR(run.frame.position(0, 0), start.x(), 1e-6);
  EXPECT_NEAR(run.frame.position(2, 0), start.z(), 1e-6);
  EXPECT_LT(run.frame.quat(0).angularDistance(attitude), 1e-5);
}

TEST_P(BackendContract, StartsFreeRingsAtTheInitialVelocity) {
  json document = lone_ring({0.0, 0.0, 0.0});
  document["gravity"] = {0.0, 0.0, 0.0};
  const Vec3 v(0.1, 0.0, -0.05);  // m/s
  document["initial_velocity"] = {v.x(), v.y(), v.z()};
  auto run = sim(document);
  EXPECT_LT((run.frame.velocity.col(0) - v).norm(), 1e-9 * v.norm());
  const Vec3 start = run.frame.position.col(0);
  const double t = 0.1;  // s
  run.advance(t);
  const Vec3 moved = run.frame.position.col(0) - start;
  // straight along v; drag may slow it (by at most 28 % in 0.1 s at 5.4/s) but never speeds it up
  EXPECT_GT(moved.normalized().dot(v.normalized()), 1.0 - 1e-9);
  EXPECT_LE(moved.norm(), v.norm() * t * (1.0 + 1e-9));
  EXPECT_GT(moved.norm(), 0.5 * v.norm() * t);
}

TEST_P(BackendContract, PinsHoldExactly) {
  // a curtain pinned along its top edge, every free ring thrown out of its plane
  json document = sheet(3, 4, "xy");
  document["pins"] = {{{"edge", "top"}}};
  document["initial_velocity"] = {0.0, 0.0, 0.2};
  auto run = sim(document);
  const std::vector<int> pins = resolve_pins(run.scene, run.weave);
  ASSERT_EQ(pins.size(), 4u);
  const Positions rest = run.frame.position;
  for (int sample = 0; sample < 2; ++sample) {
    for (int ring : pins) {
      EXPECT_EQ(run.frame.position.col(ring), rest.col(ring)) << "ring " << ring;
      EXPECT_EQ(run.frame.velocity.col(ring).norm(), 0.0) << "ring " << ring;
    }
    run.advance(0.1);
  }
  // while the free rings swung: by millimetres (links of 8 mm, thrown at 0.2 m/s for 0.2 s)
  EXPECT_GT((run.frame.position - rest).colwise().norm().maxCoeff(), 1e-3);
}

TEST_P(BackendContract, SameSceneGivesTheSameFrames) {
  // every stage at work: pins, a collider in the way, contact between non-neighbours
  json document = sheet(3, 3, "xy");
  document["pins"] = {{{"corner", "top_left"}}};
  document["initial_velocity"] = {0.0, 0.0, 0.3};
  document["colliders"] = {{{"type", "sphere"}, {"center", {0.0, 0.0, 0.025}}, {"radius", 0.02}}};
  auto first = sim(document);
  auto second = sim(document);
  const std::uint64_t at_rest = frame_hash(first.frame);
  first.advance(0.2);
  second.advance(0.2);
  EXPECT_EQ(frame_hash(first.frame), frame_hash(second.frame));
  EXPECT_NE(frame_hash(first.frame), at_rest);  // it did move
  // and a reset backend starts over exactly
  first.restart();
  EXPECT_EQ(frame_hash(first.frame), at_rest);
  first.advance(0.2);
  EXPECT_EQ(frame_hash(first.frame), frame_hash(second.frame));
}

inline std::set<std::string> stage_names(const StageProfile& profile) {
  std::set<std::string> names;
  for (const auto& [stage, stats] : profile.stages()) names.insert(stage);
  return names;
}

TEST_P(BackendContract, StagesFollowTheScene) {
  // neither colliders nor contact between non-neighbours: those stages never run
  json plain = sheet(2, 2, "xy");
  plain["features"] = {{"self_contact", false}};
  auto run = sim(plain);
  // a reset may run a stage once to prepare the t = 0 frame (plausible orients its rings by its
  // step's "orient" stage), never a contact stage
  const std::set<std::string> at_reset = stage_names(run.profile());
  for (const auto& [stage, stats] : run.profile().stages()) EXPECT_EQ(stats.calls, 1) << stage;
  EXPECT_EQ(at_reset.count("colliders") + at_reset.count("self_contact"), 0u);
  run.advance(0.01);
  const auto& stages = run.profile().stages();
  EXPECT_GT(stages.size(), at_reset.size());
  EXPECT_EQ(stages.count("colliders"), 0u);
  EXPECT_EQ(stages.count("self_contact"), 0u);
  for (const auto& [stage, stats] : stages) EXPECT_GT(stats.calls, 0) << stage;
  // a reset forgets the stages of the run before
  run.restart();
  EXPECT_EQ(stage_names(run.profile()), at_reset) << "after a reset";
  for (const auto& [stage, stats] : run.profile().stages()) EXPECT_EQ(stats.calls, 1) << stage;

  // a sheet dropped onto a floor, rings of a row (not linked, closer than a ring's outer
  // diameter) in contact: both stages run
  json busy = sheet(3, 3, "xz");
  busy["weave"]["center"] = {0.0, 0.003, 0.0};
  busy["colliders"] = {{{"type", "plane"}, {"point", {0.0, 0.0, 0.0}}}};
  auto full = sim(busy);
  full.advance(0.1);
  EXPECT_GT(full.profile().stages().count("colliders"), 0u);
  EXPECT_GT(full.profile().stages().count("self_contact"), 0u);
}

// drop of the middle ring below the pins of an inextensible chain of equal links (length 1)
// between two pins `span` apart, with the given masses of its free rings: the static equilibrium
// (the horizontal tension H is the same in every link; bisect on it until the links span `span`)
inline double chain_middle_drop(const std::vector<double>& masses, double span) {
  double total = 0.0;
  for (double m : masses) total += m;
  const auto shape = [&](double tension, double* drop) {
    double vertical = 0.5 * total, width = 0.0, height = 0.0;
    for (std::size_t link = 0; link <= masses.size(); ++link) {
      const double angle = std::atan2(vertical, tension);
      width += std::cos(angle);
      height -= std::sin(angle);
      if (link < masses.size()) vertical -= masses[link];
      if (link == masses.size() / 2) *drop = -height;
    }
    return width;
  };
  double low = 1e-9, high = 1e9, drop = 0.0;
  for (int k = 0; k < 300; ++k) {
    const double mid = std::sqrt(low * high);
    (shape(mid, &drop) < span ? low : high) = mid;
  }
  shape(std::sqrt(low * high), &drop);
  return drop;
}

TEST_P(BackendContract, LoadsPullALoadedRingLower) {
  // a 9-ring chain between two pins at three quarters of its length, damped so that it settles
  // (the knobs of the bench's chain_catenary scene; damping does not move the equilibrium)
  const int rings = 9, middle = rings / 2;
  const double spacing = 0.75, factor = 20.0;
  json document = {
      {"name", "loaded_chain"},
      {"weave", {{"type", "chain"}, {"cols", rings}, {"plane", "xy"}, {"spacing", spacing}}},
      {"pins", {{{"corner", "top_left"}}, {{"corner", "top_right"}}}},
      {"features", {{"self_contact", false}}},
      {"duration", 2.0},
      {"backends",
       {{"plausible", {{"damping", 2.0}, {"iterations", 50}, {"shock_propagation", false}}},
        {"massspring", {{"substeps", 10}}},
        {"bullet", {{"linear_damping", 0.95}, {"angular_damping", 0.95}}},
        {"ode", {{"linear_damping", 2.0}, {"angular_damping", 2.0}}}}}};
  // the middle ring's mean drop below the pins over the last half second of two
  const auto settled_drop = [&](const json& scene) {
    auto run = sim(scene);
    const double pins = run.frame.position(1, 0);
    run.advance(1.5);
    double sum = 0.0;
    const int samples = 10;
    for (int k = 0; k < samples; ++k) {
      run.advance(0.05);
      sum += pins - run.frame.position(1, middle);
    }
    return sum / samples;
  };
  const double plain = settled_drop(document);
  document["loads"] = {{{"ring", {0, middle}}, {"mass_factor", factor}}};
  const double loaded = settled_drop(document);

  // an inextensible chain with links of one inner diameter, for scale: the load draws it from a
  // discrete catenary towards a V
  const double id = scene_from_json(document, "test").ring.inner_diameter();
  std::vector<double> masses(rings - 2, 1.0);
  const double expected_plain = id * chain_middle_drop(masses, (rings - 1) * spacing);
  masses[middle - 1] = factor;
  const double expected_loaded = id * chain_middle_drop(masses, (rings - 1) * spacing);
  std::printf("[%s] chain middle drop: %.3f mm plain, %.3f mm loaded (inextensible: %.3f, %.3f)\n",
              GetParam().c_str(), 1e3 * plain, 1e3 * loaded, 1e3 * expected_plain,
              1e3 * expected_loaded);
  // the models' links differ in length and stretch; each must show at least half the effect
  EXPECT_GT(loaded - plain, 0.5 * (expected_loaded - expected_plain));
}

// names a test by its backend: BackendContract/Every.FallsFreelyUnderGravity/plausible
inline std::string backend_param_name(const ::testing::TestParamInfo<std::string>& info) {
  return info.param;
}

}  // namespace chainmail::test
