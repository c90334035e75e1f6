// The plausible model measured against physics: rest, free fall, settling, convergence, contact
// with colliders and the catenary, each at the model's default settings.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include <nlohmann/json.hpp>

#include "core/colliders.hpp"
#include "core/geometry.hpp"
#include "core/massspring/massspring.hpp"
#include "core/metrics.hpp"
#include "core/plausible/link_distance.hpp"
#include "core/plausible/plausible.hpp"
#include "core/weave.hpp"
#include "physics_oracles.hpp"
#include "scene_file/scene_file.hpp"

namespace chainmail {
namespace {

using json = nlohmann::json;

Quat quat_of(const Orientations& o, int i) {
  return Quat(o(0, i), o(1, i), o(2, i), o(3, i));
}

// a 4-in-1 sheet of rows x cols lying flat (xz) with its centres `height` above a floor at y = 0
Scene sheet_on_floor(int rows, int cols, double height) {
  return scene_from_json(
      json{{"name", "floor"},
           {"weave",
            {{"type", "4in1"},
             {"rows", rows},
             {"cols", cols},
             {"plane", "xz"},
             {"center", {0, height, 0}}}},
           {"colliders",
            json::array({{{"type", "plane"}, {"point", {0, 0, 0}}, {"normal", {0, 1, 0}}}})},
           {"duration", 1.0}},
      "test");
}

TEST(PlausiblePhysics, SheetAtRestOnAPlaneTurnsNoRing) {
  // every ring of a sheet lying still on a plane keeps its orientation: no ring, corners included,
  // turns by more than 0.1 degree in a step once the sheet has come to rest
  const Scene scene = sheet_on_floor(8, 8, 0.002);
  const Weave weave = make_weave(scene.weave, scene.ring);
  PlausibleSim sim;
  sim.reset(scene, weave, PlausibleSettings{});
  const double dt = 0.004;
  for (int s = 0; s < 250; ++s) sim.step(dt);  // settle for 1 s
  double worst = 0.0;                          // rad per step
  int worst_ring = -1;
  for (int s = 0; s < 100; ++s) {
    const Orientations before = sim.state().orientation;
    sim.step(dt);
    for (int i = 0; i < weave.size(); ++i) {
      const double turn = quat_of(before, i).angularDistance(quat_of(sim.state().orientation, i));
      if (turn > worst) worst = turn, worst_ring = i;
    }
  }
  std::printf("sheet at rest: largest turn %.4g deg per step (ring %d)\n",
              worst * 180.0 / std::numbers::pi, worst_ring);
  EXPECT_LT(worst, 0.1 * std::numbers::pi / 180.0) << "ring " << worst_ring;
}

// a 12 x 12 4-in-1 sheet in the air, flat, nothing to hit
Scene sheet_in_the_air() {
  return scene_from_json(json{{"name", "fall"},
                              {"weave",
                               {{"type", "4in1"},
                                {"rows", 12},
                                {"cols", 12},
                                {"plane", "xz"},
                                {"center", {0, 2.0, 0}}}},
                              {"duration", 1.0}},
                         "test");
}

double mean_height(const Positions& p) {
  return p.row(1).mean();
}

TEST(PlausiblePhysics, SheetFallsFreely) {
  // damping spares rigid motion: the sheet's centre falls g t^2 / 2 within 1 % (symplectic Euler
  // itself adds g t dt / 2, 0.8 % at 4 ms over 0.5 s)
  const Scene scene = sheet_in_the_air();
  const Weave weave = make_weave(scene.weave, scene.ring);
  PlausibleSim sim;
  sim.reset(scene, weave, PlausibleSettings{});
  const double y0 = mean_height(sim.state().position);
  for (int s = 0; s < 125; ++s) sim.step(0.004);
  const double fallen = y0 - mean_height(sim.state().position), expected = 0.5 * 9.81 * 0.25;
  std::printf("plausible free fall over 0.5 s: %.2f mm, g t^2/2 %.2f mm (%+.2f %%)\n", 1e3 * fallen,
              1e3 * expected, 100.0 * (fallen - expected) / expected);
  EXPECT_NEAR(fallen, expected, 0.01 * expected);
  // the former drag, for contrast: about half the fall
  PlausibleSettings drag;
  drag.damp_rigid = true;
  sim.reset(scene, weave, drag);
  for (int s = 0; s < 125; ++s) sim.step(0.004);
  EXPECT_LT(y0 - mean_height(sim.state().position), 0.6 * expected);
}

TEST(MassSpringPhysics, SheetFallsFreely) {
  // the document's damping per document step (1/2700 s), sparing rigid motion: the fall is the
  // same within 1 % with one Verlet step per document step and with ten
  const Scene scene = sheet_in_the_air();
  const Weave weave = make_weave(scene.weave, scene.ring);
  massspring::Settings settings;
  settings.point_mass = scene.ring.mass();
  const massspring::Model model = massspring::make_model(scene, weave, settings);
  const double expected = 0.5 * 9.81 * 0.25;
  for (const int substeps : {1, 10}) {
    massspring::State state = massspring::make_state(model, weave.rest_position);
    StageProfile profile;
    const double y0 = mean_height(state.position), h = 1.0 / 2700.0 / substeps;
    for (int s = 0; s < 1350 * substeps; ++s) massspring::step(model, state, h, profile);
    const double fallen = y0 - mean_height(state.position);
    std::printf("massspring free fall over 0.5 s, %d substeps: %.2f mm (%+.2f %%)\n", substeps,
                1e3 * fallen, 100.0 * (fallen - expected) / expected);
    EXPECT_NEAR(fallen, expected, 0.01 * expected) << substeps << " substeps";
  }
}

double kinetic_energy(const PlausibleSim& sim) {
  double e = 0.0;
  for (int i = 0; i < static_cast<int>(sim.model().mass.size()); ++i)
    e += 0.5 * sim.model().mass[i] * sim.state().velocity.col(i).squaredNorm();
  return e;
}

TEST(PlausiblePhysics, ChainPileSettlesInAHeap) {
  // the bench's chain pile at the default dt (4 ms), dropped exactly upright: it folds into a heap
  // on the floor (a chain whose non-neighbours kept 0.7 ID apart along the centre line stood as a
  // column 112 mm tall), comes to rest within the scene's second and keeps every link
  const Scene scene = load_scene_file(CHAINMAIL_SOURCE_DIR "/bench/scenes/chain_pile.json");
  const Weave weave = make_weave(scene.weave, scene.ring);
  const int steps = static_cast<int>(std::lround(scene.duration / 0.004));
  PlausibleSim sim;
  sim.reset(scene, weave, PlausibleSettings{});
  for (int s = 0; s < steps; ++s) sim.step(0.004);
  const double energy = kinetic_energy(sim);
  std::printf("chain pile after %.1f s: kinetic energy %.3g J\n", scene.duration, energy);
  EXPECT_LT(energy, 1e-5);

  RingFrame frame;
  sim.frame(frame);
  const RingGeometry& ring = scene.ring;
  const double outer = ring.centre_radius + ring.wire_radius;  // m
  // a heap: no ring higher than two rings lying on one standing on its rim
  const double top = frame.position.row(1).maxCoeff();  // m
  std::printf("chain pile: highest ring centre %.1f mm\n", 1e3 * top);
  EXPECT_LT(top, 3.0 * outer);
  for (const RingPair& link : weave.links) {
    EXPECT_TRUE(circles_linked(ring_circle(frame.position.col(link.a),
                                           quat_of(frame.orientation, link.a), ring.centre_radius),
                               ring_circle(frame.position.col(link.b),
                                           quat_of(frame.orientation, link.b), ring.centre_radius)))
        << "link " << link.a << "-" << link.b << " lost";
  }
}

TEST(PlausiblePhysics, NoLinkBeyondTheRingsOnAnyBenchScene) {
  // at the default settings (sweeps in substeps under the stretch control, Newton steps where a
  // link would pass the inner diameter) no linked pair of any bench scene is ever farther apart
  // than the inner diameter, sampled like the bench
  for (const char* name :
       {"curtain", "corner_hang", "table_cloth", "chain_pile", "chain_catenary", "sphere_drape"}) {
    SCOPED_TRACE(name);
    const Scene scene =
        load_scene_file(std::string(CHAINMAIL_SOURCE_DIR "/bench/scenes/") + name + ".json");
    const Weave weave = make_weave(scene.weave, scene.ring);
    PlausibleSim sim;
    sim.reset(scene, weave, PlausibleSettings{});
    const double dt = 0.004;
    const int steps = static_cast<int>(std::lround(scene.duration / dt));
    const int every = std::max(1, static_cast<int>(std::lround(scene.sample_interval / dt)));
    double peak = 0.0, residual = 0.0;
    for (int s = 1; s <= steps; ++s) {
      sim.step(dt);
      residual = std::max(residual, sim.state().residual / sim.model().longest_link);
      if (s % every != 0 && s != steps) continue;
      RingFrame frame;
      sim.frame(frame);
      MetricOptions options;
      options.other_pairs = false;
      peak = std::max(peak, measure(frame, weave, scene, options).max_stretch);
    }
    std::printf("%s: peak max_stretch %.4f, largest residual %.2g of the link length\n", name, peak,
                residual);
    EXPECT_LE(peak, 1.0);
  }
}

TEST(PlausiblePhysics, CornerHungSheetFoldsOutOfItsPlane) {
  // hung by its two top corners, a 4-in-1 sheet pushes the rows under the top edge together; its
  // rings, leaning like coins, slide over each other out of the plane and the slack folds, as
  // the rigid-ring models' sheets do (14 to 20 mm), given row_slip. With the pushes along the
  // centre lines (row_slip 0, the default) nothing breaks the sheet's mirror symmetry through its
  // plane: it hangs flat
  Scene scene = load_scene_file(CHAINMAIL_SOURCE_DIR "/bench/scenes/corner_hang.json",
                                {"weave.rows=16", "weave.cols=16", "duration=1"});
  const Weave weave = make_weave(scene.weave, scene.ring);
  const auto out_of_plane = [&](double slip) {
    PlausibleSettings settings;
    settings.row_slip = slip;
    PlausibleSim sim;
    sim.reset(scene, weave, settings);
    for (int s = 0; s < 250; ++s) sim.step(0.004);
    const Positions& p = sim.state().position;
    // the rest plane through the first row's ends and the last ring
    const Positions& rest = weave.rest_position;
    const int end_of_row = scene.weave.cols - 1, last = weave.size() - 1;
    const Vec3 normal =
        (rest.col(end_of_row) - rest.col(0)).cross(rest.col(last) - rest.col(0)).normalized();
    double far = 0.0;  // m
    for (int i = 0; i < p.cols(); ++i) {
      far = std::max(far, std::abs((p.col(i) - rest.col(0)).dot(normal)));
    }
    return far;
  };
  EXPECT_EQ(out_of_plane(PlausibleSettings{}.row_slip), 0.0);
  const double folded = out_of_plane(0.1);
  std::printf("corner-hung 16 x 16: farthest ring %.1f mm out of the plane\n", 1e3 * folded);
  EXPECT_GT(folded, 0.005);
}

// how deep a ring's torus reaches into a collider, m (<= 0: clear of it): the tube of radius a
// around the centre circle, sampled at 256 points of the circle (exact for a plane: the lowest
// point along the normal n is centre.n - (c sqrt(1 - (axis.n)^2) + a))
double torus_depth(const Collider& collider, const Vec3& centre, const Quat& q,
                   const RingGeometry& ring) {
  double depth = -1e300;
  for (int k = 0; k < 256; ++k) {
    const double s = 2.0 * std::numbers::pi * k / 256.0;
    Vec3 normal;
    const double d =
        collider_distance(collider, centre_circle_point(centre, q, ring.centre_radius, s), normal);
    depth = std::max(depth, ring.wire_radius - d);
  }
  return depth;
}

TEST(PlausiblePhysics, SubstepsFollowTheStateNotTheRingCount) {
  // a hanging sheet at rest takes few substeps at any size (the control holds its count while the
  // sweeps leave between half and all of its level); a ring thrown at 20 m/s takes as many as
  // keep its move a quarter of the inner diameter a substep
  for (const int side : {6, 24}) {
    SCOPED_TRACE(side);
    json doc = {{"name", "hang"},
                {"weave", {{"type", "4in1"}, {"rows", side}, {"cols", side}, {"plane", "xy"}}},
                {"pins", json::array({{{"edge", "top"}}})},
                {"duration", 1.0}};
    const Scene scene = scene_from_json(doc, "test");
    PlausibleSim sim;
    sim.reset(scene, make_weave(scene.weave, scene.ring), PlausibleSettings{});
    for (int s = 0; s < 500; ++s) sim.step(0.004);
    EXPECT_EQ(sim.state().speed_substeps, 1);
    EXPECT_LE(sim.state().substeps, PlausibleSim::kMinSubsteps + 2);
  }
  json doc = {{"name", "throw"},
              {"weave", {{"type", "4in1"}, {"rows", 1}, {"cols", 1}}},
              {"initial_velocity", {20.0, 0.0, 0.0}},
              {"duration", 1.0}};
  const Scene scene = scene_from_json(doc, "test");
  PlausibleSettings settings;
  settings.damping = 0.0;
  PlausibleSim sim;
  sim.reset(scene, make_weave(scene.weave, scene.ring), settings);
  const double dt = 0.004;
  sim.step(dt);
  const double move = (20.0 + 9.81 * dt) * dt;  // m, over the next step at least
  const int expected = static_cast<int>(
      std::ceil(move / (PlausibleSim::kMovePerSubstep * scene.ring.inner_diameter())));
  EXPECT_GE(sim.state().speed_substeps, expected);
  EXPECT_LE(sim.state().speed_substeps, expected + 1);
}

TEST(PlausiblePhysics, DrapedSheetAtRestTakesTheSubstepsItsLinksNeed) {
  // the bench's table cloth at rest: the control reads the links' stretch alone, so it holds the
  // fewest substeps that keep the stretch one sweep a substep leaves (falling with the square of
  // the count) at its target, and no more: one substep fewer would pass the target
  const std::string bench = CHAINMAIL_SOURCE_DIR "/bench/scenes/";
  const Scene scene = load_scene_file(
      bench + "table_cloth.json",
      {"weave.rows=16", "weave.cols=16", "colliders.0.radius=0.03", "support.radius=0.03"});
  PlausibleSim sim;
  sim.reset(scene, make_weave(scene.weave, scene.ring), PlausibleSettings{});
  for (int s = 0; s < 250; ++s) sim.step(0.004);
  const double longest = sim.model().longest_link;                      // m
  const double headroom = scene.ring.inner_diameter() / longest - 1.0;  // of it
  const double stretch = sim.state().scheduled_stretch / longest;       // of it
  const int n = sim.state().substeps;
  std::printf("table cloth at rest: %d substeps, stretch %.4f of the longest link\n", n, stretch);
  ASSERT_GT(n, PlausibleSim::kMinSubsteps);  // it needs more than the fewest
  EXPECT_LE(stretch, 0.75 * headroom);       // within the control level
  const double fewer = stretch * (n * n) / ((n - 1.0) * (n - 1.0));
  EXPECT_GT(fewer, PlausibleSim::kStretchTarget * headroom);
  EXPECT_LE(sim.max_over_extension(), 0.75 * headroom);
}

// the stability suite's heavy_weight: a ring 100 times heavier at the bottom of a 6 x 6 curtain
struct HeavyWeight {
  Scene scene = load_scene_file(CHAINMAIL_SOURCE_DIR "/bench/scenes/stability/heavy_weight.json");
  Weave weave = make_weave(scene.weave, scene.ring);
  PlausibleSim sim;
  HeavyWeight() { sim.reset(scene, weave, PlausibleSettings{}); }
  double potential() const {
    double e = 0.0;  // J
    for (int i = 0; i < weave.size(); ++i)
      e -= sim.model().mass[i] * scene.gravity.dot(sim.state().position.col(i));
    return e;
  }
};

TEST(PlausiblePhysics, HeavyRingHangingFromTheSheetComesToRest) {
  // heavy_weight at the default dt: with its way to the pins swept again it comes to rest, the
  // kinetic energy left after a second under a thousandth of the potential energy the sheet gave
  // up (the sweeps alone kept about a hundredth moving for seconds)
  HeavyWeight heavy;
  const Scene& scene = heavy.scene;
  PlausibleSim& sim = heavy.sim;
  ASSERT_FALSE(sim.model().carried.empty());
  const double start = heavy.potential(), dt = 0.004;
  double most_late = 0.0;  // J, the most kinetic energy over the last 0.2 s
  for (int s = 0; s < 250; ++s) {
    sim.step(dt);
    if (s >= 200) most_late = std::max(most_late, kinetic_energy(sim));
  }
  const double released = start - heavy.potential();  // J
  std::printf("heavy weight: %.3g J released, at most %.3g J moving after 0.8 s\n", released,
              most_late);
  EXPECT_GT(released, 0.0);
  EXPECT_LE(most_late, 1e-3 * released);
  // no link past the inner diameter
  EXPECT_LE(sim.max_over_extension(), scene.ring.inner_diameter() / sim.model().longest_link - 1.0);
}

TEST(PlausiblePhysics, HeavyRingUnderASmallSheetAtTheLargestStepComesToRest) {
  // heavy_weight at dt 0.1 s, three steps: the run ends with at most a hundredth of the energy
  // gravity gave it still moving (the harness's settled). The first step takes the substeps its
  // speed asks for (gravity alone moves a ring a dozen inner diameters in it): with the four it
  // took before, the heavy ring was thrown into a swing that ended the run with 2.7 % moving
  HeavyWeight heavy;
  const Scene& scene = heavy.scene;
  PlausibleSim& sim = heavy.sim;
  const double start = heavy.potential(), dt = 0.1;
  sim.step(dt);
  const int limit_moves =
      static_cast<int>(std::ceil(scene.gravity.norm() * dt * dt /
                                 (PlausibleSim::kMovePerSubstep * scene.ring.inner_diameter())));
  EXPECT_EQ(sim.state().speed_substeps, std::min(limit_moves, PlausibleSim::kMaxSubsteps));
  sim.step(dt);
  sim.step(dt);
  const double given = start - heavy.potential(), moving = kinetic_energy(sim);  // J
  std::printf("heavy weight at dt 0.1 s: %.3g J given, %.3g J moving after 0.3 s\n", given, moving);
  EXPECT_GT(given, 0.0);
  EXPECT_LE(moving, 0.01 * given);
}

TEST(PlausiblePhysics, SheetOfEqualRingsCarriesNoRing) {
  // the extra sweeps of a heavy ring's way to the pins are for rings kCarriedMassRatio heavier
  // than a ring they hang from: a sheet of equal rings has none
  const Scene scene = load_scene_file(CHAINMAIL_SOURCE_DIR "/bench/scenes/curtain.json");
  PlausibleSim sim;
  sim.reset(scene, make_weave(scene.weave, scene.ring), PlausibleSettings{});
  EXPECT_TRUE(sim.model().carried.empty());
}

TEST(PlausiblePhysics, SheetHittingABallAtTheLargestStepKeepsItsLinks) {
  // the stability suite's impact (a 6 x 6 sheet at 10 m/s onto a ball) at dt 0.1 s: substeps for
  // the speed and the Newton correction where the sweeps leave a link past the rings
  const Scene scene = load_scene_file(CHAINMAIL_SOURCE_DIR "/bench/scenes/stability/impact.json");
  const Weave weave = make_weave(scene.weave, scene.ring);
  PlausibleSim sim;
  sim.reset(scene, weave, PlausibleSettings{});
  double peak = 0.0;
  for (int s = 0; s < 2; ++s) {
    sim.step(0.1);
    RingFrame frame;
    sim.frame(frame);
    MetricOptions options;
    options.other_pairs = false;
    peak = std::max(peak, measure(frame, weave, scene, options).max_stretch);
  }
  std::printf("impact at dt 0.1 s: peak max_stretch %.4f\n", peak);
  EXPECT_LE(peak, 1.0);
}

TEST(PlausiblePhysics, RingsAtRestStayOutOfTheFloor) {
  // the collider keeps each ring's whole torus out, whatever its tilt: a sheet dropped on a floor
  // comes to rest with no torus deeper than 0.1 a into it
  const Scene scene = sheet_on_floor(12, 12, 0.006);
  const Weave weave = make_weave(scene.weave, scene.ring);
  PlausibleSim sim;
  sim.reset(scene, weave, PlausibleSettings{});
  for (int s = 0; s < 375; ++s) sim.step(0.004);
  const Collider& floor = scene.colliders.front();
  double deepest = -1e300;
  int ring = -1;
  for (int i = 0; i < weave.size(); ++i) {
    const double depth = torus_depth(floor, sim.state().position.col(i),
                                     quat_of(sim.state().orientation, i), scene.ring);
    if (depth > deepest) deepest = depth, ring = i;
  }
  std::printf("sheet on a floor: deepest torus %.3f a into it (ring %d), speed %.2g m/s\n",
              deepest / scene.ring.wire_radius, ring, sim.state().velocity.cwiseAbs().maxCoeff());
  EXPECT_LT(sim.state().velocity.cwiseAbs().maxCoeff(), 1e-3);  // at rest
  EXPECT_LE(deepest, 0.1 * scene.ring.wire_radius) << "ring " << ring;
}

TEST(LinkLength, FromTheRingGeometry) {
  const RingGeometry ring = RingGeometry::from_diameters(0.0016, 0.008, 7850.0);
  const double inner = ring.inner_diameter();
  // perpendicular rings of a chain reach the inner diameter: the wire of one against the far
  // inside of the other
  EXPECT_NEAR(exact_max_link_distance(ring, Vec3::UnitY(), Vec3::UnitZ(), Vec3::UnitX()), inner,
              1e-9);
  // turned towards each other they touch sooner: the largest distance shrinks with the turn; at
  // it the pair is linked and clear (to 1e-9 relative), just beyond it the tori touch
  double previous = inner;
  for (const double turn : {0.3, 0.5, 0.7}) {
    const Vec3 first(std::sin(turn), std::cos(turn), 0.0);  // axis turned towards the other ring
    const double d = exact_max_link_distance(ring, first, Vec3::UnitZ(), Vec3::UnitX());
    EXPECT_GT(d, 0.0) << turn;
    EXPECT_LT(d, previous + 1e-12) << turn;
    previous = d;
    const Circle one{Vec3::Zero(), first, ring.centre_radius};
    // (the search's closest points and core/geometry's distance agree to round-off, not bitwise)
    const Circle at{(1.0 - 1e-9) * d * Vec3::UnitX(), Vec3::UnitZ(), ring.centre_radius};
    const Circle beyond{(d + 1e-6) * Vec3::UnitX(), Vec3::UnitZ(), ring.centre_radius};
    EXPECT_TRUE(circles_linked(one, at));
    EXPECT_FALSE(circles_closer_than(one, at, 2.0 * ring.wire_radius).has_value());
    EXPECT_TRUE(circles_closer_than(one, beyond, 2.0 * ring.wire_radius).has_value());
  }
  EXPECT_LT(previous, 0.9 * inner);
  // the model's own turns: a chain reaches ID; 4-in-1 neighbours at the paper's swivel a/c lie
  // too nearly in one plane to link without touching (no distance); swivelled farther they do
  const Weave chain = make_weave(WeaveSpec{.type = WeaveType::chain, .cols = 3}, ring);
  EXPECT_NEAR(weave_max_link_distance(chain, ring, 0.0), inner, 1e-9);
  const Weave sheet =
      make_weave(WeaveSpec{.type = WeaveType::four_in_one, .rows = 3, .cols = 3}, ring);
  EXPECT_EQ(weave_max_link_distance(sheet, ring, ring.wire_radius / ring.centre_radius), 0.0);
  const double fitted = weave_max_link_distance(sheet, ring, 0.8);
  EXPECT_GT(fitted, 0.5 * inner);
  EXPECT_LT(fitted, inner);
}

using test::catenary_sag;

TEST(PlausiblePhysics, ChainHangsAsTheCatenary) {
  // chains of 40, 60 and 80 rings between two pins at equal height, links of the geometric
  // length (n - 1) ID: at the default settings the sag is the analytic catenary's within 3 %
  for (const int rings : {40, 60, 80}) {
    SCOPED_TRACE(rings);
    const Scene scene = scene_from_json(
        json{{"name", "catenary"},
             {"weave", {{"type", "chain"}, {"cols", rings}, {"plane", "xy"}, {"spacing", 0.75}}},
             {"pins", json::array({{{"corner", "top_left"}}, {{"corner", "top_right"}}})},
             {"features", {{"self_contact", false}}},
             {"duration", 4.0}},
        "test");
    const Weave weave = make_weave(scene.weave, scene.ring);
    PlausibleSim sim;
    sim.reset(scene, weave, PlausibleSettings{});
    for (int s = 0; s < 750; ++s) sim.step(0.004);
    const double before = sim.state().position(1, 0) - sim.state().position.row(1).minCoeff();
    for (int s = 0; s < 250; ++s) sim.step(0.004);
    const Positions& p = sim.state().position;
    const double span = (p.col(rings - 1) - p.col(0)).norm();
    const double expected = catenary_sag(span, (rings - 1) * scene.ring.inner_diameter());
    const double sag = p(1, 0) - p.row(1).minCoeff();
    std::printf("catenary, %d rings: sag %.2f mm, analytic %.2f mm (%+.2f %%)\n", rings, 1e3 * sag,
                1e3 * expected, 100.0 * (sag - expected) / expected);
    EXPECT_NEAR(sag, expected, 0.03 * expected);
    EXPECT_NEAR(sag, before, 0.005 * expected);  // the shape holds still over the last second
  }
}

}  // namespace
}  // namespace chainmail
