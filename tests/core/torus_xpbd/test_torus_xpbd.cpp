// The rigid-torus XPBD model (core/torus_xpbd/torus_xpbd.hpp) against closed forms: a ring at rest
// on every collider type within 0.02 a of its surface, a ring hanging from a pinned ring with the
// contact where the wires hook, bounces that never gain energy, a corner-hung sheet's links no
// deeper than the capsule references', determinism and sleeping.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "backends/collider_cases.hpp"
#include "core/circle_contact.hpp"
#include "core/colliders.hpp"
#include "core/metrics.hpp"
#include "core/torus_xpbd/torus_xpbd.hpp"
#include "scene_file/scene_file.hpp"

namespace chainmail {
namespace {

using json = nlohmann::json;

constexpr double kDt = 0.005;  // s, the backend's default step

// a scene, its layout and the model reset on them, stepped at kDt
struct Sim {
  Scene scene;
  Weave weave;
  TorusXpbdSim sim;
  Sim(const json& document, const TorusXpbdSettings& settings, const Quat* orientation = nullptr)
      : scene(scene_from_json(document, "test")), weave(make_weave(scene.weave, scene.ring)) {
    if (orientation) {
      for (int i = 0; i < weave.size(); ++i)
        weave.rest_orientation.col(i) << orientation->w(), orientation->x(), orientation->y(),
            orientation->z();
    }
    sim.reset(scene, weave, settings);
  }
  void advance(double seconds) {
    for (long long k = std::llround(seconds / kDt); k > 0; --k) {
      sim.step(kDt);
      ASSERT_TRUE(sim.finite());
    }
  }
  const TorusXpbdState& state() const { return sim.state(); }
};

json one_ring(double height) {
  return {{"name", "one_ring"},
          {"weave", {{"type", "4in1"}, {"rows", 1}, {"cols", 1}, {"center", {0, height, 0}}}},
          {"duration", 1.0}};
}

// how deep the exact torus (every point within a of the centre circle) is inside the collider:
// the centre circle densely sampled
double torus_depth(const Collider& collider, const TorusXpbdState& state, double c, double a) {
  const CircleFrame circle = ring_frame(state.position[0], state.orientation[0], c);
  double nearest = 1e300;
  for (int k = 0; k < 3600; ++k) {
    const double s = 2.0 * std::numbers::pi * k / 3600;
    Vec3 normal;
    nearest =
        std::min(nearest, collider_distance(collider, circle.at(std::cos(s), std::sin(s)), normal));
  }
  return a - nearest;
}

TEST(TorusXpbd, RestsOnEveryColliderTypeWithinTwoHundredthsOfTheWireRadius) {
  const double top = 0.01;  // m, each collider's top surface
  for (const json& collider : test::colliders_with_top_at(top)) {
    for (const double tilt : {0.0, 0.6}) {
      SCOPED_TRACE(collider["type"].get<std::string>() + " tilt " + std::to_string(tilt));
      json document = one_ring(top + 0.01);
      document["colliders"] = {collider};
      const Quat leaning(Eigen::AngleAxisd(tilt, Vec3(1, 0, 1).normalized()));
      Sim run(document, TorusXpbdSettings{}, &leaning);
      run.advance(0.8);
      const double a = run.scene.ring.wire_radius, c = run.scene.ring.centre_radius;
      const double depth = torus_depth(run.scene.colliders[0], run.state(), c, a);
      EXPECT_LE(depth, 0.02 * a);
      EXPECT_GE(depth, -0.02 * a) << "resting on it, not above it";
      EXPECT_LT(run.state().velocity[0].norm(), 1e-3);
    }
  }
}

// a ring lying on a plane (friction mu) under gravity tilted by a tangential pull of 1.2 mu times
// its weight's normal part: Coulomb's cone lets it slide in any direction, with acceleration
// (1.2 - 1) mu g; the pyramid of two tangent axes (x and z for this plane, as ODE's dPlaneSpace)
// slides along an axis alike, but holds on the diagonal, where each axis takes 1.2 / sqrt 2 < 1
TEST(TorusXpbd, FrictionConeSlidesWhereThePyramidHoldsOnTheDiagonal) {
  const double mu = 0.5, g = 9.81, pull = 1.2 * mu * g, t = 0.5;
  const double slide = 0.5 * (pull - mu * g) * t * t;  // m, the cone's slide in t
  const Quat flat = Quat::Identity();                  // the ring's axis along y
  for (const bool diagonal : {false, true}) {
    for (const bool pyramid : {false, true}) {
      SCOPED_TRACE(std::string(diagonal ? "diagonal" : "along x") +
                   (pyramid ? " pyramid" : " cone"));
      json document = one_ring(0.0008);
      document["colliders"] = {{{"type", "plane"}, {"friction", mu}}};
      const Vec3 along = diagonal ? Vec3(1, 0, 1).normalized() : Vec3(1, 0, 0);
      document["gravity"] = {pull * along.x(), -g, pull * along.z()};
      TorusXpbdSettings settings;
      settings.friction_law = pyramid ? FrictionLaw::pyramid : FrictionLaw::cone;
      Sim run(document, settings, &flat);
      const Vec3 start = run.state().position[0];
      run.advance(t);
      const Vec3 moved = run.state().position[0] - start;
      if (pyramid && diagonal) {
        EXPECT_LT(moved.norm(), 0.01 * slide);  // held (static friction creeps a little)
      } else {
        EXPECT_NEAR(moved.dot(along), slide, 0.1 * slide);
        EXPECT_LT((moved - moved.dot(along) * along).norm(), 1e-3 * slide);
      }
    }
  }
}

TEST(TorusXpbd, ARingSlidingToRestStopsWhereCoulombSaysWithAnyNumberOfVelocityPasses) {
  // a flat ring thrown along a plane at v0 stops after v0^2 / (2 mu g): each velocity pass takes
  // friction's impulse from what the earlier ones left of mu times the normal impulse, so more
  // passes do not brake harder
  const double mu = 0.4, g = 9.81, v0 = 0.2;
  const double stop = v0 * v0 / (2.0 * mu * g);  // m
  const Quat flat = Quat::Identity();
  for (const int passes : {1, 8, 32}) {
    SCOPED_TRACE("velocity passes " + std::to_string(passes));
    json document = one_ring(0.0008);
    document["colliders"] = {{{"type", "plane"}, {"friction", mu}}};
    document["initial_velocity"] = {v0, 0.0, 0.0};
    TorusXpbdSettings settings;
    settings.velocity_iterations = passes;
    Sim run(document, settings, &flat);
    const Vec3 start = run.state().position[0];
    run.advance(2.0 * v0 / (mu * g));  // twice the time it takes to stop
    EXPECT_NEAR(run.state().position[0].x() - start.x(), stop, 0.05 * stop);
    EXPECT_LT(run.state().velocity[0].norm(), 1e-3 * v0);
  }
}

TEST(TorusXpbd, ARingHangsFromAPinnedRingWhereTheWiresHook) {
  // two chain links, the first pinned in the x/y plane: the second slides to the bottom of the
  // first's wire and hangs there (no friction to hold it aside), its centre the inner diameter
  // below the first's, the two centre circles 2a apart at the first's lowest point
  const json document = {
      {"name", "two_links"},
      {"weave", {{"type", "chain"}, {"cols", 2}, {"plane", "xy"}, {"spacing", 0.9}}},
      {"pins", {{{"ring", 0}}}},
      {"duration", 1.0}};
  TorusXpbdSettings settings;
  settings.friction = 0.0;
  settings.damping = 5.0;
  Sim run(document, settings);
  run.advance(3.0);
  const RingGeometry& ring = run.scene.ring;
  const double a = ring.wire_radius, c = ring.centre_radius;
  const Vec3 top = run.state().position[0], hanging = run.state().position[1];
  EXPECT_NEAR(hanging.x(), top.x(), 0.02 * a);
  EXPECT_NEAR(hanging.z(), top.z(), 0.02 * a);
  EXPECT_NEAR(top.y() - hanging.y(), ring.inner_diameter(), 0.02 * a);
  const ClosestPoints contact = closest_points(ring_frame(top, run.state().orientation[0], c),
                                               ring_frame(hanging, run.state().orientation[1], c));
  EXPECT_NEAR(contact.distance, 2.0 * a, 0.02 * a);
  EXPECT_LT((contact.first - (top - c * Vec3::UnitY())).norm(), 0.05 * a);
  EXPECT_LT(run.state().velocity[1].norm(), 1e-3);
}

TEST(TorusXpbd, AFrictionlessBounceNeverGainsEnergy) {
  for (const double restitution : {0.0, 0.5, 1.0}) {
    for (const double tilt : {0.0, 0.3, 1.2}) {
      SCOPED_TRACE("restitution " + std::to_string(restitution) + " tilt " + std::to_string(tilt));
      json document = one_ring(0.02);
      document["colliders"] = {{{"type", "plane"}, {"point", {0, 0, 0}}, {"friction", 0.0}}};
      TorusXpbdSettings settings;
      settings.restitution = restitution;
      const Quat leaning(Eigen::AngleAxisd(tilt, Vec3::UnitX()));
      Sim run(document, settings, &leaning);
      const double start = run.sim.energy();
      double highest = start, rebound = 0.0;
      bool landed = false;
      for (int k = 0; k < 400; ++k) {
        run.advance(kDt);
        highest = std::max(highest, run.sim.energy());
        landed |= run.state().position[0].y() < 0.005;
        if (landed) rebound = std::max(rebound, run.state().position[0].y());
      }
      EXPECT_LE(highest, start * (1.0 + 1e-12));
      // it did bounce, as high as its restitution lets it (the energy goes as e^2, some into spin)
      if (restitution == 1.0) {
        EXPECT_GT(rebound, 0.01);
      } else if (restitution == 0.0) {
        EXPECT_LT(rebound, 0.005);
      }
    }
  }
}

// eight rings of a chain falling onto a floor and folding onto each other
json pile() {
  return {{"name", "pile"},
          {"weave", {{"type", "chain"}, {"cols", 8}, {"plane", "yx"}, {"center", {0, 0.04, 0}}}},
          {"colliders", {{{"type", "plane"}, {"point", {0, 0, 0}}}}},
          {"features", {{"self_contact", true}}},
          {"duration", 1.0}};
}

TEST(TorusXpbd, TheSameSceneGivesTheSameHash) {
  Sim first(pile(), TorusXpbdSettings{}), second(pile(), TorusXpbdSettings{});
  RingFrame frame;
  first.sim.frame(frame);
  const std::uint64_t start = frame_hash(frame);
  first.advance(0.3);
  second.advance(0.3);
  first.sim.frame(frame);
  const std::uint64_t end = frame_hash(frame);
  second.sim.frame(frame);
  EXPECT_EQ(frame_hash(frame), end);
  EXPECT_NE(end, start);
  // and a reset starts over exactly
  first.sim.reset(first.scene, first.weave, TorusXpbdSettings{});
  first.advance(0.3);
  first.sim.frame(frame);
  EXPECT_EQ(frame_hash(frame), end);
}

TEST(TorusXpbd, OneAndTwoThreadsGiveTheSameHash) {
  // a 10 x 10 sheet (enough rings for two threads) dropped on a sphere: collider contacts, links
  // across both halves and the seam, and pairs found by self-contact
  const json document = {
      {"name", "drop"},
      {"weave",
       {{"type", "4in1"}, {"rows", 10}, {"cols", 10}, {"plane", "xz"}, {"center", {0, 0.03, 0}}}},
      {"colliders", {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 0.02}}}},
      {"features", {{"self_contact", true}}},
      {"duration", 1.0}};
  Sim one(document, TorusXpbdSettings{}), two(document, TorusXpbdSettings{});
  two.sim.set_threads(2);
  // the halves split the sheet evenly
  const std::vector<char>& part = one.sim.ring_part();
  EXPECT_EQ(std::count(part.begin(), part.end(), 1), one.weave.size() / 2);
  one.advance(0.15);
  two.advance(0.15);
  RingFrame first, second;
  one.sim.frame(first);
  two.sim.frame(second);
  EXPECT_EQ(frame_hash(first), frame_hash(second));
  EXPECT_FALSE(one.sim.other_pairs().empty());
  // it fell onto the sphere and lies on it
  EXPECT_LT(first.position.row(1).maxCoeff(), 0.03);
  EXPECT_GT(first.position.row(1).maxCoeff(), 0.02);
}

TEST(TorusXpbd, TheLaterVelocityPassesSolveOnlyContactsNearColliders) {
  // the first two velocity passes solve every contact, the later ones those near colliders: a
  // hanging sheet touches none, and two passes or eight step it alike; a sheet dropped on a small
  // sphere hangs over it, so its later passes solve some of its contacts but not all
  const auto run = [](const json& document, int passes, double seconds) {
    TorusXpbdSettings settings;
    settings.velocity_iterations = passes;
    auto sim = std::make_unique<Sim>(document, settings);
    sim->advance(seconds);
    return sim;
  };
  const auto hash = [](const Sim& sim) {
    RingFrame frame;
    sim.sim.frame(frame);
    return frame_hash(frame);
  };
  const Scene curtain = load_scene_file(CHAINMAIL_SOURCE_DIR "/bench/scenes/curtain.json",
                                        {"weave.rows=6", "weave.cols=6"});
  const json hanging = scene_to_json(curtain);
  EXPECT_EQ(hash(*run(hanging, 2, 0.1)), hash(*run(hanging, 8, 0.1)));
  EXPECT_NE(hash(*run(hanging, 1, 0.1)), hash(*run(hanging, 2, 0.1)));
  const json drop = {
      {"name", "drop"},
      {"weave",
       {{"type", "4in1"}, {"rows", 14}, {"cols", 14}, {"plane", "xz"}, {"center", {0, 0.011, 0}}}},
      {"colliders", {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 0.01}}}},
      {"duration", 1.0}};
  const auto two = run(drop, 2, 0.1), eight = run(drop, 8, 0.1);
  EXPECT_NE(hash(*two), hash(*eight));
  // in the last step: two passes over every contact, the six more over those near the sphere
  const long long every = two->sim.velocity_solves();
  EXPECT_GT(eight->sim.velocity_solves(), every);
  EXPECT_LT(eight->sim.velocity_solves(), 3 * every);  // all eight: 4 times (here 2.1)
}

TEST(TorusXpbd, APairsClearanceIsALowerBoundOnItsCirclesDistance) {
  // a pair is scanned for new minima only where its circles may have come within reach since the
  // last scan: the bound it keeps must never exceed the exact distance (32 samples, refined), in a
  // chain whose end hits the floor at 1.5 m/s and folds onto itself
  Scene scene =
      load_scene_file(CHAINMAIL_SOURCE_DIR "/bench/scenes/chain_pile.json", {"weave.cols=20"});
  const Weave weave = make_weave(scene.weave, scene.ring);
  TorusXpbdSim sim;
  sim.reset(scene, weave, TorusXpbdSettings{});
  const double c = scene.ring.centre_radius;
  int bounded = 0;  // pair-steps whose bound says the circles are apart
  for (int k = 0; k < 120; ++k) {
    {
      sim.step(kDt);
      ASSERT_TRUE(sim.finite());
    }
    const TorusXpbdState& state = sim.state();
    for (const auto* pairs : {&sim.link_pairs(), &sim.other_pairs()}) {
      for (const RingPairContact& pair : *pairs) {
        const double exact =
            closest_points(ring_frame(state.position[pair.a], state.orientation[pair.a], c),
                           ring_frame(state.position[pair.b], state.orientation[pair.b], c))
                .distance;
        ASSERT_LE(pair.clear, exact + 1e-12)
            << "rings " << pair.a << ", " << pair.b << " at step " << k;
        bounded += pair.clear > 2.0 * scene.ring.wire_radius;
      }
    }
  }
  EXPECT_GT(bounded, 0);
}

TEST(TorusXpbd, AHangingSheetSplitsIntoHalvesThatEachHoldTheirShareOfThePins) {
  const Scene scene = load_scene_file(CHAINMAIL_SOURCE_DIR "/bench/scenes/curtain.json",
                                      {"weave.rows=8", "weave.cols=8"});
  const Weave weave = make_weave(scene.weave, scene.ring);
  TorusXpbdSim sim;
  sim.reset(scene, weave, TorusXpbdSettings{});
  int pinned[2] = {0, 0};
  for (int i = 0; i < weave.size(); ++i)
    if (sim.model().inverse_mass[i] == 0.0) ++pinned[static_cast<int>(sim.ring_part()[i])];
  EXPECT_GT(pinned[0], 0);
  EXPECT_LE(std::abs(pinned[0] - pinned[1]), 1);
}

TEST(TorusXpbd, FallingChainsPileUpWithoutPassingThroughThemselves) {
  // the bench's chain pile at several lengths: the chain's end hits the floor at 1.5 m/s and the
  // rest folds onto it; every link must stay linked and no other pair may become linked
  for (const int rings : {20, 30, 50}) {
    SCOPED_TRACE(std::to_string(rings) + " rings");
    Scene scene = load_scene_file(CHAINMAIL_SOURCE_DIR "/bench/scenes/chain_pile.json",
                                  {"weave.cols=" + std::to_string(rings)});
    const Weave weave = make_weave(scene.weave, scene.ring);
    TorusXpbdSim sim;
    sim.reset(scene, weave, TorusXpbdSettings{});
    RingFrame frame;
    for (int sample = 0; sample < 10; ++sample) {
      for (int k = 0; k < 24; ++k) {
        sim.step(kDt);
        ASSERT_TRUE(sim.finite());
      }
      sim.frame(frame);
      const Metrics m = measure(frame, weave, scene);
      ASSERT_EQ(m.broken_links, 0) << "t = " << frame.t;
      ASSERT_EQ(m.false_links, 0) << "t = " << frame.t;
    }
  }
}

TEST(TorusXpbd, ASheetHungFromTwoCornersHoldsItsLinksShallowerThanTheCapsuleReferences) {
  // the bench's corner_hang: two links at each pinned corner carry half the sheet's weight. The
  // deepest linked pair, from the exact centre-circle distance, stays shallower all the way than
  // the 0.045 a the capsule references leave at rest (it settles near 0.015 a; the swing's first
  // jerk reaches 0.04 a)
  const Scene scene =
      load_scene_file(CHAINMAIL_SOURCE_DIR "/bench/scenes/corner_hang.json", {"duration=1"});
  const Weave weave = make_weave(scene.weave, scene.ring);
  TorusXpbdSim sim;
  sim.reset(scene, weave, TorusXpbdSettings{});
  RingFrame frame;
  MetricOptions options;
  options.other_pairs = false;
  double deepest = 0.0;  // m
  for (int sample = 0; sample < 20; ++sample) {
    for (int k = 0; k < 10; ++k) {
      sim.step(kDt);
      ASSERT_TRUE(sim.finite());
    }
    sim.frame(frame);
    const Metrics m = measure(frame, weave, scene, options);
    EXPECT_EQ(m.broken_links, 0) << "t = " << frame.t;
    deepest = std::max(deepest, m.penetration_max_linked);
  }
  EXPECT_LE(deepest, 0.045 * scene.ring.wire_radius);
}

TEST(TorusXpbd, ARingAtRestSleepsAndWakesWhenHit) {
  json document = one_ring(0.002);
  document["colliders"] = {{{"type", "plane"}, {"point", {0, 0, 0}}}};
  TorusXpbdSettings settings;
  settings.sleeping = true;
  const Quat flat = Quat::Identity();
  Sim run(document, settings, &flat);
  run.advance(1.0);
  ASSERT_TRUE(run.state().asleep[0]);
  const Vec3 resting = run.state().position[0];
  run.advance(0.5);
  EXPECT_EQ(run.state().position[0], resting);  // not integrated: it does not creep
  // a blow from below (the floor moved into it) moves it and wakes it
  run.sim.mutable_state().position[0].y() -= 0.2 * run.scene.ring.wire_radius;
  run.advance(0.05);
  EXPECT_FALSE(run.state().asleep[0]);
}

}  // namespace
}  // namespace chainmail
