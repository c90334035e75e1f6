#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <set>
#include <stdexcept>
#include <utility>

#include "core/geometry.hpp"
#include "core/plausible/orientation.hpp"
#include "core/plausible/plausible.hpp"
#include "scene_file/scene_file.hpp"

namespace chainmail {
namespace {

using json = nlohmann::json;

Scene curtain(int rows, int cols) {
  return scene_from_json(json{{"name", "curtain"},
                              {"weave",
                               {{"type", "4in1"},
                                {"rows", rows},
                                {"cols", cols},
                                {"plane", "xy"},
                                {"center", {0, 0.3, 0}}}},
                              {"pins", json::array({{{"edge", "top"}}})},
                              {"duration", 1.0}},
                         "test");
}

TEST(Plausible, OverExtensionShrinksWithIterations) {
  // plain Gauss-Seidel sweeps (no outward pass, no Newton steps): the stretch left after a step
  // falls as the sweep count grows, and vanishes at a high count
  const Scene scene = curtain(30, 30);
  const Weave weave = make_weave(scene.weave, scene.ring);
  std::vector<double> residual;
  for (int iterations : {1, 4, 16, 64, 256, 1024, 4096}) {
    PlausibleSettings settings;
    settings.iterations = iterations;
    settings.shock_propagation = false;
    settings.tolerance = 0.0;  // the sweeps alone, every one of them
    settings.newton_steps = 0;
    settings.substeps = 1;
    settings.pin_attachments = false;
    PlausibleSim sim;
    sim.reset(scene, weave, settings);
    // disturb the sheet first: every free ring displaced by up to 1.5 mm (same seed every time)
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-0.0015, 0.0015);
    for (int i = 0; i < weave.size(); ++i) {
      const Vec3 kick(u(rng), u(rng), u(rng));
      if (sim.model().inverse_mass[i] > 0) sim.mutable_state().position.col(i) += kick;
    }
    sim.step(0.004);
    residual.push_back(sim.max_over_extension());
    std::printf("iterations %5d: max over-extension %.3g\n", iterations, residual.back());
  }
  for (size_t k = 1; k < residual.size(); ++k) EXPECT_LE(residual[k], residual[k - 1] + 1e-12);
  EXPECT_LT(residual[3], 0.5 * residual[0]);
  EXPECT_GT(residual.front(), 1e-3);
  EXPECT_LT(residual.back(), 1e-6);
}

TEST(Plausible, OutwardPassRemovesHangingStretch) {
  // the outward pass with the paper's rule (no compression limits): with four sweeps and no Newton
  // steps, the diagonal bounds undo its one-sided moves
  const Scene scene = curtain(30, 30);
  const Weave weave = make_weave(scene.weave, scene.ring);
  PlausibleSettings settings;
  settings.iterations = 4;
  settings.newton_steps = 0;
  settings.substeps = 1;
  settings.pin_attachments = false;
  settings.shock_propagation = true;
  settings.compression_limits = false;
  PlausibleSim sim;
  sim.reset(scene, weave, settings);
  for (int s = 0; s < 250; ++s) sim.step(0.004);
  EXPECT_LT(sim.max_over_extension(), 0.05);
}

TEST(Plausible, PinnedRingsNeverMove) {
  const Scene scene = curtain(12, 12);
  const Weave weave = make_weave(scene.weave, scene.ring);
  PlausibleSim sim;
  sim.reset(scene, weave, PlausibleSettings{});
  const std::vector<int> pinned = resolve_pins(scene, weave);
  ASSERT_EQ(pinned.size(), 12u);
  for (int s = 0; s < 300; ++s) sim.step(0.004);
  for (int i : pinned) {
    EXPECT_EQ(sim.state().position.col(i), weave.rest_position.col(i)) << "ring " << i;
  }
  // and the rest did move
  EXPECT_GT((sim.state().position - weave.rest_position).norm(), 0.01);
}

TEST(Plausible, FreeFallWithoutConstraintsMatchesHalfGTSquared) {
  const Scene scene = scene_from_json(json{{"name", "drop"},
                                           {"weave", {{"type", "4in1"}, {"rows", 1}, {"cols", 1}}},
                                           {"duration", 1.0}},
                                      "test");
  const Weave weave = make_weave(scene.weave, scene.ring);
  const double dt = 0.001, g = 9.81, t = 0.5;
  // one substep a step: symplectic Euler, exactly g dt^2 n (n + 1) / 2 = g t^2 / 2 + g t dt / 2;
  // automatic substeps: the same with the substep h for dt, within g t h / 2 of g t^2 / 2
  for (const int substeps : {1, 0}) {
    PlausibleSettings settings;
    settings.damping = 0.0;
    settings.substeps = substeps;
    PlausibleSim sim;
    sim.reset(scene, weave, settings);
    const double y0 = sim.state().position(1, 0);
    for (int s = 0; s < 500; ++s) sim.step(dt);
    const double fallen = y0 - sim.state().position(1, 0);
    if (substeps == 1) {
      EXPECT_NEAR(fallen, 0.5 * g * t * t + 0.5 * g * t * dt, 1e-9);
    } else {
      EXPECT_GE(sim.state().substeps, PlausibleSim::kMinSubsteps);
      EXPECT_NEAR(fallen, 0.5 * g * t * t, 0.5 * g * t * dt / PlausibleSim::kMinSubsteps + 1e-12);
      EXPECT_NEAR(fallen, 0.5 * g * t * t, 0.01 * 0.5 * g * t * t);
    }
  }
}

TEST(Plausible, SheetDroppedOnPlaneRestsWithoutSinking) {
  const Scene scene = scene_from_json(
      json{{"name", "rest"},
           {"weave",
            {{"type", "4in1"},
             {"rows", 10},
             {"cols", 10},
             {"plane", "xz"},
             {"center", {0, 0.02, 0}}}},
           {"colliders",
            json::array({{{"type", "plane"}, {"point", {0, 0, 0}}, {"normal", {0, 1, 0}}}})},
           {"duration", 1.0}},
      "test");
  const Weave weave = make_weave(scene.weave, scene.ring);
  PlausibleSim sim;
  sim.reset(scene, weave, PlausibleSettings{});
  for (int s = 0; s < 500; ++s) sim.step(0.004);
  // a ring's centre stays at least a (lying flat) and at most c + a (on its rim) above the plane,
  // within the solver's tolerance
  const RingGeometry& ring = scene.ring;
  const double tolerance = sim.model().settings.tolerance * sim.model().longest_link;
  EXPECT_GE(sim.state().position.row(1).minCoeff(), ring.wire_radius - tolerance);
  EXPECT_LT(sim.state().position.row(1).maxCoeff(), ring.centre_radius + ring.wire_radius);
  EXPECT_LT(sim.state().velocity.cwiseAbs().maxCoeff(), 1e-3);  // at rest
}

TEST(Orientation, Eq1GivesOrthonormalRightHandedBasis) {
  const Vec3 pairs[][2] = {{Vec3(1, 0, 0), Vec3(0, 0, 1)},
                           {Vec3(1, 0.2, 0.3), Vec3(0.4, -0.1, 1)},
                           {Vec3(2, 0, 0), Vec3(1.5, 0, 0.2)},
                           {Vec3(-0.3, 1, 0.2), Vec3(0.1, 0.1, -2)}};
  for (const auto& pair : pairs) {
    const Mat3 m = orthonormal_basis_eq1(pair[0], pair[1]);
    EXPECT_NEAR((m.transpose() * m - Mat3::Identity()).norm(), 0.0, 1e-12);
    EXPECT_NEAR(m.determinant(), 1.0, 1e-12);
    // y is normal to both neighbour directions; x', z' sit symmetrically about their bisector
    EXPECT_NEAR(m.col(1).dot(pair[0]), 0.0, 1e-12);
    EXPECT_NEAR(m.col(1).dot(pair[1]), 0.0, 1e-12);
    const Vec3 bisector = (pair[0].normalized() + pair[1].normalized()).normalized();
    EXPECT_NEAR(m.col(0).dot(bisector), std::sqrt(0.5), 1e-12);
    EXPECT_NEAR(m.col(2).dot(bisector), std::sqrt(0.5), 1e-12);
  }
}

TEST(Orientation, SwivelFromExtendedToCompressed) {
  const RingGeometry ring = RingGeometry::from_diameters(0.0016, 0.008, 7850.0);
  const double a_over_c = ring.wire_radius / ring.centre_radius;
  const double min_ratio = 0.2;
  EXPECT_DOUBLE_EQ(swivel_angle(1.0, min_ratio, a_over_c), a_over_c);
  EXPECT_DOUBLE_EQ(swivel_angle(min_ratio, min_ratio, a_over_c), 0.5 * std::numbers::pi);
  double previous = 0.0;
  for (double ratio = 1.0; ratio >= min_ratio; ratio -= 0.1) {
    const double angle = swivel_angle(ratio, min_ratio, a_over_c);
    EXPECT_GT(angle, previous);
    previous = angle;
  }
  // the model at full extension: interior rings swivel by a/c out of the eq. (1) basis
  const Scene scene = curtain(6, 6);
  Weave weave = make_weave(scene.weave, scene.ring);
  Positions stretched = weave.rest_position;
  const double max_link = 0.95 * ring.inner_diameter();
  // scale the layout so neighbours sit exactly at the maximum distance
  const double rest =
      (weave.rest_position.col(weave.links[0].a) - weave.rest_position.col(weave.links[0].b))
          .norm();
  stretched *= max_link / rest;
  Orientations orientation = weave.rest_orientation;
  orient_rings(stretched, weave, ring, OrientationSettings{max_link, true, 0.0}, orientation);
  Orientations flat = weave.rest_orientation;
  orient_rings(stretched, weave, ring, OrientationSettings{max_link, false, 0.0}, flat);
  const int interior = weave.ring_at_row_col(2, 2);
  const Quat q(orientation(0, interior), orientation(1, interior), orientation(2, interior),
               orientation(3, interior));
  const Quat f(flat(0, interior), flat(1, interior), flat(2, interior), flat(3, interior));
  EXPECT_NEAR(q.angularDistance(f), a_over_c, 1e-9);

  // the model under compression (neighbours at the wire thickness 2a): every interior ring turns
  // by pi/2 about its swivel axis, one way or the other by the weave's parity, so that neighbours
  // in adjacent rows lean opposite ways
  Positions compressed = weave.rest_position * (ring.min_link_distance() / rest);
  Orientations swivelled = weave.rest_orientation, unswivelled = weave.rest_orientation;
  orient_rings(compressed, weave, ring, OrientationSettings{max_link, true, 0.0}, swivelled);
  orient_rings(compressed, weave, ring, OrientationSettings{max_link, false, 0.0}, unswivelled);
  int positive = 0, negative = 0;
  for (int i = 0; i < weave.size(); ++i) {
    bool interior = true;
    for (int other : weave.neighbours[i]) interior &= other >= 0;
    if (!interior) continue;
    const Quat turned(swivelled(0, i), swivelled(1, i), swivelled(2, i), swivelled(3, i));
    const Quat plain(unswivelled(0, i), unswivelled(1, i), unswivelled(2, i), unswivelled(3, i));
    // the turn in the ring's own frame, about its swivel axis (1, 0, -1)/sqrt(2) (equal spacing)
    const Quat relative = plain.conjugate() * turned;
    const double along = relative.vec().dot(Vec3(1.0, 0.0, -1.0).normalized());
    const double signed_angle = 2.0 * std::atan2(along, relative.w());
    EXPECT_NEAR(std::abs(signed_angle), 0.5 * std::numbers::pi, 1e-9) << "ring " << i;
    EXPECT_EQ(signed_angle > 0 ? 1 : -1, weave.parity[i]) << "ring " << i;
    (signed_angle > 0 ? positive : negative) += 1;
  }
  EXPECT_GT(positive, 0);
  EXPECT_GT(negative, 0);
}

// penetrating pairs among interior neighbours (both rings with four neighbours) of a sheet whose
// neighbours all sit at the maximum link distance
int penetrating_neighbours_at_full_extension(const RingGeometry& ring, double extended) {
  const Scene scene = curtain(6, 6);
  const Weave weave = make_weave(scene.weave, ring);
  const double max_link = 0.95 * ring.inner_diameter();
  const double rest =
      (weave.rest_position.col(weave.links[0].a) - weave.rest_position.col(weave.links[0].b))
          .norm();
  const Positions stretched = weave.rest_position * (max_link / rest);
  Orientations orientation = weave.rest_orientation;
  orient_rings(stretched, weave, ring, OrientationSettings{max_link, true, extended}, orientation);
  int penetrating = 0;
  auto interior = [&](int k) {
    for (int other : weave.neighbours[k]) {
      if (other < 0) return false;
    }
    return true;
  };
  for (const RingPair& link : weave.links) {
    if (!interior(link.a) || !interior(link.b)) continue;
    auto circle = [&](int k) {
      const Quat q(orientation(0, k), orientation(1, k), orientation(2, k), orientation(3, k));
      return ring_circle(stretched.col(k), q, ring.centre_radius);
    };
    const Circle first = circle(link.a), second = circle(link.b);
    EXPECT_TRUE(circles_linked(first, second));
    penetrating += tori_interpenetrate(first, second, ring.wire_radius, 1e-3 * ring.wire_radius);
  }
  return penetrating;
}

TEST(Orientation, FittedSwivelClearsNeighboursWhereAOverCDoesNot) {
  // the paper's a/c at full extension leaves AR-5 neighbours interpenetrating; the fitted angle,
  // larger, leaves every neighbour pair linked and clear, for every aspect ratio the weave allows
  for (double aspect : {4.0, 5.0, 6.0, 8.0}) {
    SCOPED_TRACE(aspect);
    const RingGeometry ring = RingGeometry::from_diameters(0.0016, 0.0016 * aspect, 7850.0);
    const double fitted = fitted_extended_swivel(ring, 0.95 * ring.inner_diameter());
    const double a_over_c = ring.wire_radius / ring.centre_radius;
    EXPECT_GT(fitted, a_over_c);
    EXPECT_LT(fitted, 0.5 * std::numbers::pi);
    EXPECT_EQ(penetrating_neighbours_at_full_extension(ring, fitted), 0);
    if (aspect == 5.0) {
      EXPECT_GT(penetrating_neighbours_at_full_extension(ring, a_over_c), 0);
    }
  }
}

// a 12 x 12 sheet above a small sphere, its sides folding in under it as it drapes
Scene fold_over_sphere() {
  return scene_from_json(
      json{{"name", "fold"},
           {"weave",
            {{"type", "4in1"},
             {"rows", 12},
             {"cols", 12},
             {"plane", "xz"},
             {"center", {0, 0.06, 0}}}},
           {"colliders",
            json::array({{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 0.02}}})},
           {"duration", 1.0}},
      "test");
}

TEST(Plausible, ContactCandidatesHoldEveryPairInRange) {
  // a sheet folding over a small sphere, its sides folding in under it: at every step each
  // non-neighbour pair closer than the repulsion range must be in the reused candidate list, and
  // the list is rebuilt far less often than every step
  const Scene scene = fold_over_sphere();
  const Weave weave = make_weave(scene.weave, scene.ring);
  // the paper's rule: the weave's compression limits would hold the sides apart, out of range
  PlausibleSettings settings;
  settings.compression_limits = false;
  PlausibleSim sim;
  sim.reset(scene, weave, settings);
  const int steps = 300;
  const double range = sim.model().repulsion_range;
  long long close_pairs = 0;
  for (int s = 0; s < steps; ++s) {
    sim.step(0.004);
    const auto& p = sim.state().position;
    std::set<std::pair<int, int>> listed;
    for (const RingPair& c : sim.state().contact_candidates) listed.insert({c.a, c.b});
    for (int i = 0; i < weave.size(); ++i) {
      for (int j = i + 1; j < weave.size(); ++j) {
        const auto& nb = weave.neighbours[i];
        if (std::find(nb.begin(), nb.end(), j) != nb.end()) continue;
        // rings that share two neighbours have a minimum distance of their own
        const bool diagonal = std::abs(weave.grid[i][0] - weave.grid[j][0]) == 1 &&
                              std::abs(weave.grid[i][1] - weave.grid[j][1]) == 1;
        if (diagonal) continue;
        // in contact: within a hundredth of the range (the sweeps leave a pressed pair at it,
        // measured along the direction it had at the start of the step: a little beyond it)
        if ((p.col(i) - p.col(j)).norm() > 1.01 * range) continue;
        ++close_pairs;
        ASSERT_TRUE(listed.count({i, j})) << "pair " << i << "," << j << " missed at step " << s;
      }
    }
  }
  EXPECT_GT(close_pairs, 0);  // the fold does bring rings into contact
  EXPECT_LT(sim.state().contact_rebuilds, steps / 2);
}

// the oracle of GridKeys::constrained: linked neighbours from the lists, and with the diagonals
// rings one row and one column apart on the grid
bool listed_pair(const Weave& weave, bool diagonals, int a, int b) {
  const std::array<int, 4>& nb = weave.neighbours[a];
  if (std::find(nb.begin(), nb.end(), b) != nb.end()) return true;
  return diagonals && std::abs(weave.grid[a][0] - weave.grid[b][0]) == 1 &&
         std::abs(weave.grid[a][1] - weave.grid[b][1]) == 1;
}

TEST(Plausible, PackedGridNamesTheNeighbourListsPairs) {
  // every pair of rings within three cells of each other, as the packed grid and as the lists
  // say: a 4-in-1 sheet with and without diagonals, the same with its rows numbered from 70000
  // (past 16 bits), a grid, and a chain longer than 16 bits of columns
  const Scene sheet = fold_over_sphere();
  const Weave four = make_weave(sheet.weave, sheet.ring);
  Weave shifted = four;
  for (auto& g : shifted.grid) g[0] += 70000;
  WeaveSpec long_chain;
  long_chain.type = WeaveType::chain;
  long_chain.rows = 1, long_chain.cols = 70001;
  const Weave chain = make_weave(long_chain, sheet.ring);
  WeaveSpec grid_spec = sheet.weave;
  grid_spec.type = WeaveType::grid;
  grid_spec.spacing = 0.006;
  const Weave grid = make_weave(grid_spec, sheet.ring);
  long long checked = 0, constrained = 0;
  for (const Weave* weave : std::initializer_list<const Weave*>{&four, &shifted, &chain, &grid}) {
    for (const bool diagonals : {true, false}) {
      const GridKeys keys = grid_keys(*weave, diagonals);
      const int n = weave->size();
      for (int a = 0; a < n; a += weave == &chain ? 97 : 1) {
        for (int b = 0; b < n; ++b) {
          if (std::abs(weave->grid[a][0] - weave->grid[b][0]) > 3 ||
              std::abs(weave->grid[a][1] - weave->grid[b][1]) > 3 || a == b) {
            continue;
          }
          const bool expected = listed_pair(*weave, diagonals, a, b);
          ASSERT_EQ(keys.constrained(a, b), expected)
              << a << "," << b << " diagonals " << diagonals;
          ++checked, constrained += expected;
        }
      }
    }
  }
  EXPECT_GT(constrained, 0);
  EXPECT_GT(checked, 2 * constrained);  // unconstrained pairs were asked too
  // a weave whose lists disagree with its grid is refused by name
  Weave broken = four;
  std::swap(broken.neighbours[5][1], broken.neighbours[5][3]);
  EXPECT_THROW(grid_keys(broken, true), std::invalid_argument);
}

TEST(Plausible, FallingSheetKeepsItsContactCandidates) {
  // a sheet dropped flat, nothing pinned: every ring falls alike, so no two rings close in and
  // the candidate list built at the start holds, however far the sheet falls (a rebuild on each
  // ring's own move would come every 2 mm of fall, a dozen times over these 0.2 s)
  const Scene scene = scene_from_json(
      json{{"name", "drop"},
           {"weave", {{"type", "4in1"}, {"rows", 16}, {"cols", 16}, {"plane", "xz"}}},
           {"features", {{"self_contact", true}}},
           {"duration", 1.0}},
      "test");
  const Weave weave = make_weave(scene.weave, scene.ring);
  PlausibleSim sim;
  sim.reset(scene, weave, PlausibleSettings{});
  const double y0 = sim.state().position(1, 0);
  for (int s = 0; s < 50; ++s) sim.step(0.004);
  const double skin = sim.model().settings.contact_skin * sim.model().repulsion_range;  // m
  EXPECT_GT(y0 - sim.state().position(1, 0), 20 * skin);
  EXPECT_EQ(sim.state().contact_rebuilds, 1);
}

// a grid of rings spaced `spacing` m apart, hung from its two top corners
Scene corner_hung_grid(double spacing) {
  return scene_from_json(
      json{{"name", "grid"},
           {"weave",
            {{"type", "grid"},
             {"rows", 6},
             {"cols", 6},
             {"plane", "xy"},
             {"center", {0, 0.3, 0}},
             {"spacing", spacing}}},
           {"pins", json::array({{{"corner", "top_left"}}, {{"corner", "top_right"}}})},
           {"duration", 1.0}},
      "test");
}

TEST(Plausible, NewtonStepsStopWhereThePinsCannotBeHeld) {
  // pins 0.1 m apart with five links of under a centimetre between them: no positions meet every
  // bound, the Newton steps' residual stalls, and they stop after kNewtonPatience steps without
  // progress instead of running to newton_steps in every substep; the later substeps of the step
  // keep the sweeps' result
  const Scene far = corner_hung_grid(0.02);
  const Weave weave = make_weave(far.weave, far.ring);
  PlausibleSim sim;
  sim.reset(far, weave, PlausibleSettings{});
  int stalled_steps = 0;
  for (int s = 0; s < 5; ++s) {
    sim.step(0.004);
    stalled_steps += sim.state().newton_stalled;
    EXPECT_LE(sim.state().newton_steps, PlausibleSim::kNewtonPatience) << "step " << s;
    EXPECT_TRUE(sim.state().position.allFinite());
  }
  EXPECT_EQ(stalled_steps, 5);
  EXPECT_GT(sim.max_over_extension(), 1.0);  // still torn: no solve can hold it
  // rings that can hang between the pins never stall (their Newton steps, where they run,
  // converge), and the sheet holds
  const Scene near = corner_hung_grid(0.006);
  const Weave close = make_weave(near.weave, near.ring);
  PlausibleSim held;
  held.reset(near, close, PlausibleSettings{});
  for (int s = 0; s < 50; ++s) {
    held.step(0.004);
    EXPECT_FALSE(held.state().newton_stalled) << "step " << s;
  }
  EXPECT_LT(held.max_over_extension(), 0.01);
}

TEST(Plausible, SameSceneTwiceSameHash) {
  const Scene scene = curtain(10, 10);
  const Weave weave = make_weave(scene.weave, scene.ring);
  std::uint64_t hashes[2];
  for (auto& h : hashes) {
    PlausibleSim sim;
    sim.reset(scene, weave, PlausibleSettings{});
    for (int s = 0; s < 100; ++s) sim.step(0.004);
    RingFrame frame;
    sim.frame(frame);
    h = frame_hash(frame);
  }
  EXPECT_EQ(hashes[0], hashes[1]);
}

TEST(Plausible, CurtainHashMatchesTheRecordedOne) {
  // the same scene, binary and settings must give the same bits on every machine of the target
  // platform (IEEE double, no fast-math). A deliberate change to the model changes this hash:
  // update the constant in the same commit and say why.
  const Scene scene = curtain(10, 10);
  const Weave weave = make_weave(scene.weave, scene.ring);
  PlausibleSim sim;
  sim.reset(scene, weave, PlausibleSettings{});
  for (int s = 0; s < 250; ++s) sim.step(0.004);
  RingFrame frame;
  sim.frame(frame);
  std::printf("curtain 10x10, 250 steps: hash %016llx\n",
              static_cast<unsigned long long>(frame_hash(frame)));
  EXPECT_EQ(frame_hash(frame), 0x082799aaa9314650ull);
}

}  // namespace
}  // namespace chainmail
