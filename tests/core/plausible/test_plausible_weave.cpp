// The plausible model beyond the paper: compression limited by the weave's geometry in both
// directions, and the swivel hinge propagated from the pins.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include <nlohmann/json.hpp>

#include "core/geometry.hpp"
#include "core/metrics.hpp"
#include "core/plausible/constraints.hpp"
#include "core/plausible/link_distance.hpp"
#include "core/plausible/neighbour_frame.hpp"
#include "core/plausible/orientation.hpp"
#include "core/plausible/pin_paths.hpp"
#include "core/plausible/plausible.hpp"
#include "core/plausible/weave_limits.hpp"
#include "scene_file/scene_file.hpp"

namespace chainmail {
namespace {

using json = nlohmann::json;

const RingGeometry kRing = RingGeometry::from_diameters(0.0016, 0.008, 7850.0);

Quat lean(double angle) {
  return Quat(Eigen::AngleAxisd(angle, Vec3::UnitZ()));  // about the row normal of an xz sheet
}

TEST(WeaveLimits, DiagonalsMeetWhereTheirToriTouch) {
  // rings in one row lean alike: stacked coins, their planes 2a apart along the row at
  // 2a / sin(lean); rings two rows apart lie in one plane along the column: rim to rim at 2(c + a)
  const double a = kRing.wire_radius, c = kRing.centre_radius;
  for (const double angle : {0.35, 0.46, 0.61}) {  // leans at which the rest layout is clear
    SCOPED_TRACE(angle);
    const WeaveLimits limits = four_in_one_limits(kRing, angle);
    EXPECT_NEAR(limits.row, 2.0 * a / std::sin(angle), 1e-9);
    EXPECT_NEAR(limits.column, 2.0 * (c + a), 1e-9);
    // linked neighbours: linked and touching at their limit, interpenetrating just inside it
    const Vec3 link = Vec3(0.5 * kFourInOneRowSpacing, 0.0, kFourInOneRowAdvance).normalized();
    const Circle mine = ring_circle(Vec3::Zero(), lean(angle), c);
    const Circle at = ring_circle(limits.link * link, lean(-angle), c);
    const Circle inside = ring_circle((limits.link - 1e-6) * link, lean(-angle), c);
    EXPECT_TRUE(circles_linked(mine, at));
    EXPECT_NEAR(circle_circle_distance(mine, at), 2.0 * a, 1e-8);
    EXPECT_LT(circle_circle_distance(mine, inside), 2.0 * a);
    EXPECT_LT(limits.link, 0.5 * kRing.inner_diameter());  // far closer than the rest layout
  }
  // the paper's swivel a/c leaves rings of one row interpenetrating even at the rest layout: no
  // closer than that, and linked neighbours keep the paper's wire thickness
  const WeaveLimits paper = four_in_one_limits(kRing, a / c);
  EXPECT_DOUBLE_EQ(paper.row, kFourInOneRowSpacing * kRing.inner_diameter());
  EXPECT_DOUBLE_EQ(paper.link, 2.0 * a);
  EXPECT_EQ(paper.row_max, std::numeric_limits<double>::infinity());
}

TEST(WeaveLimits, KnightPairsStopWhereRingsCouldPassThroughEachOther) {
  // rings of adjacent rows a row and a half apart are kept 2c apart: beyond it no two rings link,
  // however they turn; just inside it two rings whose planes both hold the line between their
  // centres do (the far rim of each reaches into the other's disk)
  const double c = kRing.centre_radius, inner = kRing.inner_diameter();
  const Vec3 rest(1.5 * kFourInOneRowSpacing * inner, 0.0, kFourInOneRowAdvance * inner);
  const WeaveLimits limits = four_in_one_limits(kRing, 0.46);
  EXPECT_DOUBLE_EQ(limits.knight, 2.0 * c);
  EXPECT_LT(limits.knight, rest.norm());  // the rest layout is clear of it
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  auto random_axis = [&] { return Vec3(normal(rng), normal(rng), normal(rng)).normalized(); };
  for (int k = 0; k < 20000; ++k) {
    const Vec3 u = random_axis();
    const Circle first{Vec3::Zero(), random_axis(), c};
    const Circle second{limits.knight * (1.0 + 1e-9) * u, random_axis(), c};
    ASSERT_FALSE(circles_linked(first, second)) << "pair " << k;
  }
  const Vec3 u = rest.normalized();
  const Circle first{Vec3::Zero(), u.cross(Vec3::UnitY()).normalized(), c};
  const Circle second{0.999 * limits.knight * u, Vec3::UnitY(), c};
  EXPECT_TRUE(circles_linked(first, second));
}

TEST(WeaveLimits, AnEdgeRingTurnedOutOfTheSheetPassesItsColumnNeighboursRim) {
  // two rings of one row, the ring of the next row linked to both at its rest spot, and a ring of
  // the row before linked to the same two and to nothing else (the sheet's edge): in the sheet's
  // plane it comes no closer to the ring two rows on than rim to rim; turned about the row, out of
  // the plane, it comes closer than 2c, linked to and clear of both, clear of and not linked to
  // the ring two rows on
  const double c = kRing.centre_radius, a = kRing.wire_radius;
  const double angle = fitted_extended_swivel(kRing, 0.95 * kRing.inner_diameter());
  const WeaveLimits limits = four_in_one_limits(kRing, angle);
  const double row = 0.5 * (limits.row + limits.row_max);
  const Circle left = ring_circle(Vec3(-0.5 * row, 0, 0), lean(angle), c);
  const Circle right = ring_circle(Vec3(0.5 * row, 0, 0), lean(angle), c);
  const Circle next = ring_circle(Vec3(0, 0, -0.5 * limits.column), lean(-angle), c);
  for (const Circle& side : {left, right}) {
    ASSERT_TRUE(circles_linked(side, next));
    ASSERT_FALSE(circles_closer_than(side, next, 2.0 * a).has_value());
  }
  // the edge ring's closest valid distance to `next` along the column, turned by `turn` (rad)
  auto closest_edge = [&](double turn) {
    double best = std::numeric_limits<double>::infinity();
    const Quat q = Quat(Eigen::AngleAxisd(turn, Vec3::UnitX())) * lean(-angle);
    for (int k = 0; k <= 112; ++k) {
      const double z = 0.5 * limits.column * k / 112.0;
      const Circle edge = ring_circle(Vec3(0, 0, z), q, c);
      bool valid = !circles_linked(edge, next) && !circles_closer_than(edge, next, 2.0 * a);
      for (const Circle& side : {left, right}) {
        valid = valid && circles_linked(side, edge) && !circles_closer_than(side, edge, 2.0 * a);
      }
      if (valid) best = std::min(best, z + 0.5 * limits.column);
    }
    return best;
  };
  EXPECT_GE(closest_edge(0.0), limits.column * (1.0 - 1e-9));
  double turned = std::numeric_limits<double>::infinity();
  for (int degrees = 5; degrees < 180; degrees += 5) {
    turned = std::min(turned, closest_edge(degrees * std::numbers::pi / 180.0));
  }
  std::printf("edge ring: in the plane %.3f ID, turned out of it %.3f ID (2c %.3f)\n",
              closest_edge(0.0) / kRing.inner_diameter(), turned / kRing.inner_diameter(),
              limits.knight / kRing.inner_diameter());
  EXPECT_LT(turned, limits.column_edge);
}

// a rhombus of four rings, the two of one row at +-row / 2 along X leaning +angle, the two of the
// rows before and after at +-column / 2 along Z leaning -angle: are its links linked and clear?
bool rhombus_holds(double angle, double row, double column) {
  const double c = kRing.centre_radius, a = kRing.wire_radius;
  const Circle left = ring_circle(Vec3(-0.5 * row, 0, 0), lean(angle), c);
  const Circle right = ring_circle(Vec3(0.5 * row, 0, 0), lean(angle), c);
  for (const double z : {-0.5 * column, 0.5 * column}) {
    const Circle shared = ring_circle(Vec3(0, 0, z), lean(-angle), c);
    for (const Circle& side : {left, right}) {
      if (!circles_linked(side, shared)) return false;
      if (circles_closer_than(side, shared, 2.0 * a - 1e-9).has_value()) return false;
    }
  }
  return true;
}

TEST(WeaveLimits, RowsStretchOnlyAsFarAsTheirSharedRingsAllow) {
  // at the widest row, with the column at its closest, the shared rings still hold both rings of
  // the row; 2 % wider they cannot, at that column or any longer one
  const double angle = fitted_extended_swivel(kRing, 0.95 * kRing.inner_diameter());
  const WeaveLimits limits = four_in_one_limits(kRing, angle);
  ASSERT_TRUE(std::isfinite(limits.row_max));
  EXPECT_TRUE(rhombus_holds(angle, limits.row_max * (1.0 - 1e-6), limits.column));
  for (const double stretch : {1.0, 1.05, 1.1, 1.2}) {
    EXPECT_FALSE(rhombus_holds(angle, 1.02 * limits.row_max, stretch * limits.column)) << stretch;
  }
  // and the rest layout lies within every limit
  const double inner = kRing.inner_diameter();
  EXPECT_GT(kFourInOneRowSpacing * inner, limits.row);
  EXPECT_LT(kFourInOneRowSpacing * inner, limits.row_max);
  EXPECT_GT(2.0 * kFourInOneRowAdvance * inner, limits.column);
}

TEST(EdgeConstraint, AnEdgeAtItsMaximumStaysThere) {
  // an edge placed at its maximum length lands a rounding above or below it; one above must be
  // pulled in by that rounding, not to its minimum (its square root can equal the maximum)
  const double min_length = 0.0018, max_length = 0.0077477;
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  int corrected = 0;
  for (int k = 0; k < 20000; ++k) {
    const Vec3 p0(normal(rng) * 0.01, normal(rng) * 0.01, normal(rng) * 0.01);
    const Vec3 u = Vec3(normal(rng), normal(rng), normal(rng)).normalized();
    const Vec3 p1 = p0 + max_length * u;
    Vec3 corr0, corr1;
    if (solve_edge_constraint(p0, 0.0, p1, 1.0, min_length, max_length, corr0, corr1) == 0.0)
      continue;
    ++corrected;
    ASSERT_LT(corr1.norm(), 1e-15) << "edge " << k << " moved by " << corr1.norm() << " m";
  }
  EXPECT_GT(corrected, 0);  // some land above
}

// an 8 x 8 sheet in the plane y = 0, no gravity, nothing to hit
Scene loose_sheet(const json& pins = json::array()) {
  return scene_from_json(
      json{{"name", "press"},
           {"weave",
            {{"type", "4in1"}, {"rows", 8}, {"cols", 8}, {"plane", "xz"}, {"center", {0, 0, 0}}}},
           {"pins", pins},
           {"gravity", {0, 0, 0}},
           {"duration", 1.0}},
      "test");
}

// whether a ring has no link to the row before it ((i - 1, j), (i, j + 1)) or none to the row
// after it ((i + 1, j), (i, j - 1)): it lies in the sheet's first or last row
bool in_end_row(const Weave& weave, int ring) {
  const auto& n = weave.neighbours[ring];  // (i - 1, j), (i + 1, j), (i, j - 1), (i, j + 1)
  return (n[0] < 0 && n[3] < 0) || (n[1] < 0 && n[2] < 0);
}

// all pairs; pairs of rings within the sheet's rows; pairs with a ring of the first or last row
enum class Rings { all, interior, edge };

// the smallest distance among the sheet's pairs (i, j)-(i + di, j + dj) of this kind, m
double closest(const Weave& weave, const Positions& p, int dj, int di = 1,
               Rings rings = Rings::all) {
  double best = std::numeric_limits<double>::infinity();
  for (int a = 0; a < weave.size(); ++a) {
    for (int b = 0; b < weave.size(); ++b) {
      if (weave.grid[b][0] != weave.grid[a][0] + di || weave.grid[b][1] != weave.grid[a][1] + dj)
        continue;
      const bool edge = in_end_row(weave, a) || in_end_row(weave, b);
      if (rings == Rings::interior && edge) continue;
      if (rings == Rings::edge && !edge) continue;
      best = std::min(best, (p.col(a) - p.col(b)).norm());
    }
  }
  return best;
}

TEST(WeaveLimits, ColumnPairsWithAnEdgeRingKeepTheKnightsRule) {
  // column pairs meet rim to rim; a pair with a ring of the first or last row keeps only 2c (a
  // ring at a row's end is linked to the rows on both sides: it keeps the rim)
  const Weave weave = make_weave(loose_sheet().weave, kRing);
  const WeaveLimits limits = four_in_one_limits(kRing, 0.46);
  EXPECT_DOUBLE_EQ(limits.column_edge, 2.0 * kRing.centre_radius);
  int edge = 0, interior = 0;
  for (const DiagonalPair& pair : diagonal_pairs(weave, limits)) {
    const auto &a = weave.grid[pair.a], &b = weave.grid[pair.b];
    if (b[0] - a[0] != a[1] - b[1]) continue;  // not a column pair
    const bool on = in_end_row(weave, pair.a) || in_end_row(weave, pair.b);
    (on ? edge : interior) += 1;
    EXPECT_DOUBLE_EQ(pair.min, on ? limits.column_edge : limits.column) << pair.a << " " << pair.b;
  }
  EXPECT_GT(edge, 0);
  EXPECT_GT(interior, 0);
}

TEST(PlausibleWeave, SheetPushedTogetherInBothDirectionsStopsAtTheDerivedDistances) {
  // every ring is driven toward the sheet's centre along the row and along the column at once
  // (the compression the paper assumes never happens): the columns close up until rings two rows
  // apart meet rim to rim at 2(c + a), or at 2c where one lies in the first or last row; the
  // rows until rings of adjacent rows a row and a half apart are 2c apart, before the rings of
  // one row stack at 2a / sin(lean)
  const Scene scene = loose_sheet();
  const Weave weave = make_weave(scene.weave, scene.ring);
  const double a = scene.ring.wire_radius, c = scene.ring.centre_radius;
  // closest (i + 1, j + 1), (i + 1, j - 1) and (i + 2, j + 1), with and without limits
  double row[2], column[2], knight[2], column_edge = 0.0;
  for (const bool limits : {true, false}) {
    PlausibleSettings settings;
    settings.compression_limits = limits;
    settings.damping = 0.0;
    PlausibleSim sim;
    sim.reset(scene, weave, settings);
    const Vec3 centre = weave.rest_position.rowwise().mean();
    for (int s = 0; s < 250; ++s) {
      for (int i = 0; i < weave.size(); ++i) {
        sim.mutable_state().velocity.col(i) = -2.0 * (sim.state().position.col(i) - centre);
      }
      sim.step(0.004);
    }
    row[limits] = closest(weave, sim.state().position, 1);
    column[limits] = closest(weave, sim.state().position, -1, 1, Rings::interior);
    if (limits) column_edge = closest(weave, sim.state().position, -1, 1, Rings::edge);
    knight[limits] = std::min(closest(weave, sim.state().position, 1, 2),
                              closest(weave, sim.state().position, 2, 1));
    if (limits) {
      // within 1 %: pressed every step, the sweeps end a little short of converged
      const double lean = sim.model().extended_swivel;
      std::printf(
          "pushed sheet: rows close to %.3f mm (2a / sin(lean) %.3f), columns to %.3f mm "
          "(2(c + a) %.3f), at the edge %.3f mm (2c), pairs a row and a half apart to %.3f mm "
          "(2c %.3f)\n",
          1e3 * row[1], 2e3 * a / std::sin(lean), 1e3 * column[1], 2e3 * (c + a), 1e3 * column_edge,
          1e3 * knight[1], 2e3 * c);
      EXPECT_GT(row[1], 0.99 * 2.0 * a / std::sin(lean));
      EXPECT_NEAR(column[1], 2.0 * (c + a), 0.01 * column[1]);
      EXPECT_GT(column_edge, 0.99 * 2.0 * c);
      EXPECT_LT(column_edge, 0.99 * 2.0 * (c + a));
      EXPECT_NEAR(knight[1], 2.0 * c, 0.01 * knight[1]);
    }
  }
  // the paper's rule lets all go far closer: only the non-neighbour minimum distance holds them
  std::printf("paper's rule: rows %.3f mm, columns %.3f mm, a row and a half %.3f mm\n",
              1e3 * row[0], 1e3 * column[0], 1e3 * knight[0]);
  EXPECT_LT(column[0], 0.8 * column[1]);
  EXPECT_LT(knight[0], 0.8 * knight[1]);
}

TEST(PlausibleWeave, CornerHungSheetKeepsItsLinks) {
  // an 8 x 8 sheet hung from its two top corners for a second: every neighbour pair still links,
  // and no rings a row and a half apart link, though the sag pushes the sides together along the
  // rows (the stacked rings of one row, turned toward different pins, may still cross: counted)
  Scene scene = loose_sheet(json::array({{{"corner", "top_left"}}, {{"corner", "top_right"}}}));
  scene.gravity = Vec3(0.0, -9.81, 0.0);
  scene.weave.plane = SheetPlane::xy;
  const Weave weave = make_weave(scene.weave, scene.ring);
  PlausibleSim sim;
  sim.reset(scene, weave, PlausibleSettings{});
  for (int s = 0; s < 250; ++s) sim.step(0.004);
  RingFrame frame;
  sim.frame(frame);
  const Metrics m = measure(frame, weave, scene);
  int knights_linked = 0;
  const double c = scene.ring.centre_radius;
  for (int a = 0; a < weave.size(); ++a) {
    for (int b = 0; b < weave.size(); ++b) {
      const int di = weave.grid[b][0] - weave.grid[a][0], dj = weave.grid[b][1] - weave.grid[a][1];
      if (!((di == 2 && dj == 1) || (di == 1 && dj == 2))) continue;
      knights_linked += circles_linked(ring_circle(frame.position.col(a), frame.quat(a), c),
                                       ring_circle(frame.position.col(b), frame.quat(b), c));
    }
  }
  std::printf("corner-hung 8 x 8: %lld broken, %lld false links (%d a row and a half apart)\n",
              m.broken_links, m.false_links, knights_linked);
  EXPECT_EQ(m.broken_links, 0);
  EXPECT_EQ(knights_linked, 0);
  EXPECT_LE(m.max_stretch, 1.0);
}

TEST(PinPaths, EveryRingIsPulledTowardItsPin) {
  // one pin: the steps of every path add up to the vector from the ring to the pin, exactly
  const Scene scene = loose_sheet(json::array({{{"corner", "top_left"}}}));
  const Weave weave = make_weave(scene.weave, scene.ring);
  const std::vector<int> pins = resolve_pins(scene, weave);
  const PinPaths paths = pin_paths(weave, pins);
  EXPECT_EQ(paths.order.size(), static_cast<size_t>(weave.size() - 1));  // all but the pin
  Positions pull;
  pull_toward_pins(paths, weave.rest_position, pull);
  for (int i = 0; i < weave.size(); ++i) {
    const Vec3 expected = weave.rest_position.col(pins[0]) - weave.rest_position.col(i);
    EXPECT_LT((pull.col(i) - expected).norm(), 1e-12) << "ring " << i;
  }
  // two pins: a ring fewer links from one of them is pulled toward that one alone
  const Scene two = loose_sheet(json::array({{{"corner", "top_left"}}, {{"corner", "top_right"}}}));
  const std::vector<int> corners = resolve_pins(two, weave);
  const PinPaths both = pin_paths(weave, corners);
  pull_toward_pins(both, weave.rest_position, pull);
  const PinPaths left = pin_paths(weave, {corners[0]}), right = pin_paths(weave, {corners[1]});
  int nearer_one = 0;
  for (int i = 0; i < weave.size(); ++i) {
    if (left.depth[i] == right.depth[i]) continue;
    const int pin = left.depth[i] < right.depth[i] ? corners[0] : corners[1];
    const Vec3 expected = weave.rest_position.col(pin) - weave.rest_position.col(i);
    EXPECT_LT((pull.col(i) - expected).norm(), 1e-12) << "ring " << i;
    ++nearer_one;
  }
  EXPECT_GT(nearer_one, weave.size() / 2);
}

// how far ring i's swivel hinge is turned from the row normal, rad (positive toward the local
// +X + Z, the row), and the sign of its lean, from its orientation and the eq. (1) frame of its
// neighbours (interior rings only)
struct Hinge {
  double turn;
  int lean;
};
Hinge hinge_of(const Weave& weave, const Positions& p, const Orientations& o, int i) {
  const auto& nb = weave.neighbours[i];
  const Mat3 basis =
      orthonormal_basis_eq1(p.col(nb[1]) - p.col(nb[0]), p.col(nb[3]) - p.col(nb[2]));
  const Quat q(o(0, i), o(1, i), o(2, i), o(3, i));
  const Eigen::AngleAxisd swivel(Quat(basis).conjugate() * q);
  const Vec3 axis = swivel.axis() * (swivel.angle() > 0 ? 1.0 : -1.0);
  const Vec3 normal = Vec3(1, 0, -1).normalized(), along = Vec3(1, 0, 1).normalized();
  // the hinge is a line: take it on the row normal's side, the lean's sign goes with it
  const int side = axis.dot(normal) >= 0.0 ? 1 : -1;
  return {std::atan2(side * axis.dot(along), side * axis.dot(normal)), side};
}

// neighbour pairs of `weave` whose centre circles do not link
int unlinked_pairs(const Weave& weave, const Positions& p, const Orientations& o) {
  const double c = kRing.centre_radius;
  int count = 0;
  for (int a = 0; a < weave.size(); ++a) {
    for (int b : weave.neighbours[a]) {
      if (b <= a) continue;
      const Quat qa(o(0, a), o(1, a), o(2, a), o(3, a)), qb(o(0, b), o(1, b), o(2, b), o(3, b));
      count += !circles_linked(ring_circle(p.col(a), qa, c), ring_circle(p.col(b), qb, c));
    }
  }
  return count;
}

TEST(PlausibleWeave, SheetFoldedOverAnEdgeKeepsEveryLink) {
  // the rest sheet folded by 90 degrees over an edge through one row of rings (a cloth over a
  // table's edge): the frames from chords across the fold tilt the rings on it about 45 degrees
  // from both their links, so the folded rings lose links; turned to keep them, every pair links,
  // and the flat sheet's orientations do not change
  const Weave weave = make_weave(loose_sheet().weave, kRing);
  const double d_max = 0.95 * kRing.inner_diameter();
  OrientationSettings settings;
  settings.max_link_distance = d_max;
  settings.extended_angle = fitted_extended_swivel(kRing, d_max);
  Orientations flat = weave.rest_orientation;
  orient_rings(weave.rest_position, weave, kRing, settings, flat);
  const Orientations unturned = flat;
  EXPECT_EQ(keep_links(weave.rest_position, weave, kRing, flat), 0);
  EXPECT_EQ(flat, unturned);
  const double edge = weave.rest_position(2, weave.size() / 2);  // z of a ring on the fold
  Positions folded = weave.rest_position;
  for (int i = 0; i < weave.size(); ++i) {
    const double beyond = folded(2, i) - edge;
    if (beyond > 0.0) folded(1, i) -= beyond, folded(2, i) = edge;
  }
  Orientations o = weave.rest_orientation;
  orient_rings(folded, weave, kRing, settings, o);
  const int before = unlinked_pairs(weave, folded, o);
  const int turned = keep_links(folded, weave, kRing, o);
  const int after = unlinked_pairs(weave, folded, o);
  std::printf("folded 8 x 8: %d pairs unlinked by the chord frames, %d after turning %d rings\n",
              before, after, turned);
  EXPECT_GT(before, 0);
  EXPECT_EQ(after, 0);
}

bool interior(const Weave& weave, int i) {
  const auto& nb = weave.neighbours[i];
  return std::all_of(nb.begin(), nb.end(), [](int k) { return k >= 0; });
}

TEST(PlausibleWeave, EveryRingSwivelsTowardThePinsItHangsFrom) {
  // a sheet pinned at one top corner: every ring's hinge turns toward that corner (by the angle
  // between the row normal and the direction to the pin, at most kMaxHingeTurn), each ring still
  // leaning the way its row does; pinned at the other corner instead, the turns follow that one
  const Weave weave = make_weave(loose_sheet().weave, kRing);
  double total[2] = {0.0, 0.0};  // sum of turns with the left pin, with the right pin
  for (const int side : {0, 1}) {
    const Scene scene = loose_sheet(json::array({{{"corner", side ? "top_right" : "top_left"}}}));
    const Vec3 pin = weave.rest_position.col(resolve_pins(scene, weave)[0]);
    PlausibleSim sim;
    sim.reset(scene, weave, PlausibleSettings{});  // orients the rest layout
    const Positions& p = sim.state().position;
    int turned = 0;
    for (int i = 0; i < weave.size(); ++i) {
      if (!interior(weave, i)) continue;
      const Hinge hinge = hinge_of(weave, p, sim.state().orientation, i);
      // the direction to the pin in the ring's own frame, as a line on the row normal's side
      const auto& nb = weave.neighbours[i];
      const Mat3 basis =
          orthonormal_basis_eq1(p.col(nb[1]) - p.col(nb[0]), p.col(nb[3]) - p.col(nb[2]));
      const Vec3 to_pin = basis.transpose() * (pin - p.col(i));
      double expected = std::atan2(to_pin.dot(Vec3(1, 0, 1).normalized()),
                                   to_pin.dot(Vec3(1, 0, -1).normalized()));
      if (expected > 0.5 * std::numbers::pi) expected -= std::numbers::pi;
      if (expected < -0.5 * std::numbers::pi) expected += std::numbers::pi;
      expected = std::clamp(expected, -kMaxHingeTurn, kMaxHingeTurn);
      EXPECT_NEAR(hinge.turn, expected, 1e-9) << "ring " << i;
      EXPECT_EQ(hinge.lean, weave.parity[i]) << "ring " << i;
      total[side] += hinge.turn;
      turned += std::abs(hinge.turn) > 0.01;
    }
    EXPECT_GT(turned, 0);
  }
  // the two corners turn the sheet's hinges opposite ways
  std::printf("mean hinge turn: %.1f deg pinned top left, %.1f deg top right\n",
              total[0] * 180.0 / std::numbers::pi / weave.size(),
              total[1] * 180.0 / std::numbers::pi / weave.size());
  EXPECT_LT(total[0] * total[1], 0.0);
  // without pins the hinge is the row normal everywhere
  PlausibleSim free;
  free.reset(loose_sheet(), weave, PlausibleSettings{});
  for (int i = 0; i < weave.size(); ++i) {
    if (!interior(weave, i)) continue;
    EXPECT_NEAR(hinge_of(weave, free.state().position, free.state().orientation, i).turn, 0.0,
                1e-9);
  }
}

TEST(NeighbourFrame, CarriesTheRestAxisWithTheSheet) {
  // a ring's rest axis, kept in its neighbour frame, comes back as the rest axis on the rest
  // layout and turned with the sheet on a turned one; a ring with no plane of neighbours has none
  const Scene scene = loose_sheet();
  const Weave weave = make_weave(scene.weave, scene.ring);
  const Positions in_frame = rest_axes_in_frame(weave);
  const Quat turn(Eigen::AngleAxisd(0.7, Vec3(0.3, -1.0, 0.4).normalized()));
  const Positions turned = (turn.toRotationMatrix() * weave.rest_position).eval();
  int framed = 0;
  for (int r = 0; r < weave.size(); ++r) {
    const Orientations& o = weave.rest_orientation;
    const Vec3 rest = Quat(o(0, r), o(1, r), o(2, r), o(3, r)) * Vec3::UnitY();
    if (in_frame.col(r).isZero()) {  // a corner with no neighbour along one grid axis
      EXPECT_EQ(axis_in_frame(weave, in_frame, turned, r), Vec3::Zero());
      continue;
    }
    ++framed;
    EXPECT_LT((axis_in_frame(weave, in_frame, weave.rest_position, r) - rest).norm(), 1e-12);
    EXPECT_LT((axis_in_frame(weave, in_frame, turned, r) - turn * rest).norm(), 1e-12);
  }
  EXPECT_GE(framed, weave.size() - 4);
  Positions collapsed = weave.rest_position;
  collapsed.colwise() = weave.rest_position.col(0);
  EXPECT_EQ(axis_in_frame(weave, in_frame, collapsed, 0), Vec3::Zero());
}

}  // namespace
}  // namespace chainmail
