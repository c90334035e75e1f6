// Metrics on hand-made frames: what each count means, checked against cases whose answer is known.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <random>

#include "core/metrics.hpp"
#include "core/weave.hpp"
#include "scene_file/scene_file.hpp"

namespace chainmail {
namespace {

using json = nlohmann::json;

struct Layout {
  Scene scene;
  Weave weave;
  RingFrame frame;  // the rest layout, at rest

  explicit Layout(const json& doc)
      : scene(scene_from_json(doc, "test")), weave(make_weave(scene.weave, scene.ring)) {
    frame.resize(weave.size());
    frame.position = weave.rest_position;
    frame.orientation = weave.rest_orientation;
    frame.velocity.setZero();
  }
};

json sheet(const std::string& type, int rows, int cols) {
  return {{"name", "metrics"},
          {"duration", 1.0},
          {"weave", {{"type", type}, {"rows", rows}, {"cols", cols}, {"plane", "xz"}}}};
}

TEST(Metrics, RestLayoutIsLinkedClearAndStill) {
  Layout s(sheet("4in1", 4, 4));
  const Metrics m = measure(s.frame, s.weave, s.scene);
  const double rest = (s.weave.rest_position.col(s.weave.links[0].a) -
                       s.weave.rest_position.col(s.weave.links[0].b))
                          .norm();
  EXPECT_NEAR(m.max_stretch, rest / s.scene.ring.max_link_distance(), 1e-12);
  EXPECT_LT(m.max_stretch, 1.0);
  EXPECT_EQ(m.penetrating_linked, 0);
  EXPECT_EQ(m.penetrating_other, 0);
  EXPECT_EQ(m.broken_links, 0);
  EXPECT_EQ(m.false_links, 0);
  EXPECT_EQ(m.kinetic_energy, 0.0);
  EXPECT_FALSE(m.drape_coefficient.has_value());  // no support in the scene
}

TEST(Metrics, RingPulledAwayBreaksItsLinks) {
  Layout s(sheet("4in1", 4, 4));
  const int ring = s.weave.ring_at_row_col(1, 1);
  int links = 0;
  for (int other : s.weave.neighbours[ring]) links += other >= 0;
  s.frame.position.col(ring) += Vec3(0.0, 0.1, 0.0);  // 10 cm up: far from every neighbour
  s.frame.velocity.col(ring) = Vec3(0.0, 2.0, 0.0);
  const Metrics m = measure(s.frame, s.weave, s.scene);
  EXPECT_EQ(m.broken_links, links);
  EXPECT_GT(m.max_stretch, 10.0);
  EXPECT_EQ(m.false_links, 0);
  EXPECT_DOUBLE_EQ(m.max_speed, 2.0);
  EXPECT_NEAR(m.kinetic_energy, 0.5 * s.scene.ring.mass() * 4.0, 1e-15);
}

TEST(Metrics, RingMovedThroughANonNeighbourIsAFalseLink) {
  // a chain 0-1-2: ring 2 moved to the mirror image of ring 1 through ring 0's centre (a circle is
  // symmetric under that reflection), so 0-2 is linked and 1-2 no longer is
  json doc = sheet("chain", 1, 3);
  doc["weave"]["spacing"] = 0.9;
  Layout s(doc);
  s.frame.position.col(2) = 2.0 * s.frame.position.col(0) - s.frame.position.col(1);
  s.frame.orientation.col(2) = s.frame.orientation.col(1);
  const Metrics m = measure(s.frame, s.weave, s.scene);
  EXPECT_EQ(m.false_links, 1);
  EXPECT_EQ(m.broken_links, 1);
  // and a ring dropped onto its neighbour's centre interpenetrates it
  Layout t(doc);
  t.frame.position.col(1) = t.frame.position.col(0);
  EXPECT_GE(measure(t.frame, t.weave, t.scene).penetrating_linked, 1);
}

TEST(Metrics, NonFiniteFramesAreCountedNotMeasured) {
  Layout s(sheet("4in1", 3, 3));
  s.frame.position(1, 4) = std::numeric_limits<double>::quiet_NaN();
  s.frame.velocity(0, 2) = std::numeric_limits<double>::infinity();
  const Metrics m = measure(s.frame, s.weave, s.scene);
  EXPECT_EQ(m.non_finite, 2);
  EXPECT_TRUE(std::isnan(m.max_stretch));
  EXPECT_TRUE(std::isnan(m.penetration_max_linked));
  EXPECT_TRUE(std::isnan(m.penetration_mean_linked));
  EXPECT_TRUE(std::isnan(m.penetration_max_other));
  EXPECT_TRUE(std::isnan(m.penetration_mean_other));
}

TEST(Metrics, DrapeCoefficientIsOneFlatAndFallsAsTheSheetHangs) {
  json doc = sheet("4in1", 12, 12);
  doc["support"] = {{"center", {0, 0, 0}}, {"radius", 0.01}};
  Layout s(doc);
  const Metrics flat = measure(s.frame, s.weave, s.scene);
  ASSERT_TRUE(flat.drape_coefficient.has_value());
  EXPECT_NEAR(*flat.drape_coefficient, 1.0, 1e-12);
  // every ring outside the support pulled in halfway towards it: less shadow, lower coefficient
  RingFrame draped = s.frame;
  for (int i = 0; i < draped.size(); ++i) {
    Vec3 p = draped.position.col(i);
    const double r = std::hypot(p.x(), p.z());
    if (r > 0.01) p.x() *= 0.5 * (1.0 + 0.01 / r), p.z() *= 0.5 * (1.0 + 0.01 / r);
    draped.position.col(i) = p;
  }
  const Metrics m = measure(draped, s.weave, s.scene);
  EXPECT_LT(*m.drape_coefficient, 0.6);
  EXPECT_GT(*m.drape_coefficient, 0.0);
  // a frame flung kilometres apart (a run blowing up) is still measured, on a coarser raster
  RingFrame flung = s.frame;
  flung.position *= 1e6;
  const Metrics far = measure(flung, s.weave, s.scene);
  ASSERT_TRUE(far.drape_coefficient.has_value());
  EXPECT_GT(*far.drape_coefficient, 1.0);
}

TEST(Metrics, ClothGridStretchIsAgainstRestLengthAndHasNoRingCounts) {
  json doc = sheet("grid", 5, 5);
  doc["weave"]["spacing"] = 0.02;
  Layout s(doc);
  EXPECT_NEAR(measure(s.frame, s.weave, s.scene).max_stretch, 1.0, 1e-12);
  s.frame.position *= 1.1;  // every edge 10 % longer
  const Metrics m = measure(s.frame, s.weave, s.scene);
  EXPECT_NEAR(m.max_stretch, 1.1, 1e-12);
  EXPECT_NEAR(m.mean_stretch, 1.1, 1e-12);
  EXPECT_EQ(m.broken_links + m.false_links + m.penetrating_linked + m.penetrating_other, 0);
}

TEST(Metrics, CoplanarRingsAreNeverLinked) {
  // every ring with one orientation, as the mass-spring baseline emits a flat sheet: neighbours
  // are coplanar, so every link is broken and nothing is falsely linked. Round-off must not decide:
  // the same holds with the sheet turned anywhere, each ring's orientation off by a few ulps (the
  // baseline computes each from its own neighbour vectors) and positions off by ~1e-12 m
  Layout s(sheet("4in1", 8, 8));
  for (int i = 0; i < s.frame.size(); ++i) s.frame.set_quat(i, Quat::Identity());
  const Metrics flat = measure(s.frame, s.weave, s.scene);
  EXPECT_EQ(flat.broken_links, static_cast<long long>(s.weave.links.size()));
  EXPECT_EQ(flat.false_links, 0);
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 40; ++trial) {
    const Quat turn = Quat(g(rng), g(rng), g(rng), g(rng)).normalized();
    const Vec3 shift = trial % 4 < 2 ? Vec3::Zero() : Vec3(g(rng), g(rng), g(rng));
    const double noise = trial % 2 ? 1e-12 : 0.0;  // m
    RingFrame moved = s.frame;
    for (int i = 0; i < moved.size(); ++i) {
      moved.position.col(i) =
          turn * s.frame.position.col(i) + shift + noise * Vec3(u(rng), u(rng), u(rng));
      Quat q = turn;
      q.coeffs() += 4e-16 * Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng));
      moved.set_quat(i, q.normalized());
    }
    const Metrics m = measure(moved, s.weave, s.scene);
    EXPECT_EQ(m.broken_links, flat.broken_links) << "trial " << trial;
    EXPECT_EQ(m.false_links, 0) << "trial " << trial;
    EXPECT_EQ(m.penetrating_linked, flat.penetrating_linked) << "trial " << trial;
    EXPECT_EQ(m.penetrating_other, flat.penetrating_other) << "trial " << trial;
    // depths move with the noise (the circles no longer meet exactly), by about its size
    EXPECT_NEAR(m.penetration_max_linked, flat.penetration_max_linked, 1e-11);
    EXPECT_NEAR(m.penetration_mean_other, flat.penetration_mean_other, 1e-11);
  }
}

TEST(Metrics, PenetrationDepthsOfKnownPairs) {
  // a chain 0-1-...-9 placed by hand in clusters 5 cm apart, all rings flat (normal +y), so every
  // depth is known in closed form (depth = 2a - centre-circle distance):
  // - rings one above the other (coaxial, height h): distance h
  // - rings side by side in one plane, centres 2c + g apart: distance g
  Layout s(sheet("chain", 1, 10));
  const double a = s.scene.ring.wire_radius, c = s.scene.ring.centre_radius;
  for (int i = 0; i < s.frame.size(); ++i) s.frame.set_quat(i, Quat::Identity());
  auto put = [&](int ring, int cluster, Vec3 offset) {
    s.frame.position.col(ring) = Vec3(0.05 * cluster, 0.0, 0.0) + offset;
  };
  put(0, 0, Vec3::Zero()), put(1, 0, Vec3(0, 0.5 * a, 0));          // linked, depth 1.5a
  put(2, 1, Vec3::Zero()), put(3, 1, Vec3(0, 1.2 * a, 0));          // linked, depth 0.8a
  put(4, 2, Vec3::Zero()), put(6, 2, Vec3(0, 1.0 * a, 0));          // other, depth 1.0a
  put(5, 3, Vec3::Zero()), put(7, 3, Vec3(2 * c + 0.3 * a, 0, 0));  // other, depth 1.7a
  put(8, 4, Vec3::Zero()), put(9, 4, Vec3(0, 2.5 * a, 0));          // linked, clear (distance 2.5a)
  const Metrics m = measure(s.frame, s.weave, s.scene);
  const double tol = 1e-9 * a;
  EXPECT_EQ(m.penetrating_linked, 2);
  EXPECT_NEAR(m.penetration_max_linked, 1.5 * a, tol);
  EXPECT_NEAR(m.penetration_mean_linked, 0.5 * (1.5 + 0.8) * a, tol);
  EXPECT_EQ(m.penetrating_other, 2);
  EXPECT_NEAR(m.penetration_max_other, 1.7 * a, tol);
  EXPECT_NEAR(m.penetration_mean_other, 0.5 * (1.0 + 1.7) * a, tol);
  // the names, in CSV order, and their values
  const std::vector<std::string>& names = metric_names();
  const auto at = std::find(names.begin(), names.end(), "penetrating_other");
  ASSERT_NE(at, names.end());
  const std::vector<std::string> depth_names(at + 1, at + 5);
  EXPECT_EQ(depth_names,
            (std::vector<std::string>{"penetration_max_linked", "penetration_mean_linked",
                                      "penetration_max_other", "penetration_mean_other"}));
  EXPECT_EQ(metric_value(m, "penetration_max_linked"), m.penetration_max_linked);
  EXPECT_EQ(metric_value(m, "penetration_mean_linked"), m.penetration_mean_linked);
  EXPECT_EQ(metric_value(m, "penetration_max_other"), m.penetration_max_other);
  EXPECT_EQ(metric_value(m, "penetration_mean_other"), m.penetration_mean_other);
  // no interpenetration at rest: every depth 0
  Layout rest(sheet("4in1", 4, 4));
  const Metrics clear = measure(rest.frame, rest.weave, rest.scene);
  EXPECT_EQ(clear.penetration_max_linked + clear.penetration_mean_linked +
                clear.penetration_max_other + clear.penetration_mean_other,
            0.0);
}

// a chain of n rings pinned at both ends, level, with span / length = 1 / sinh(1): the catenary
// y = A cosh(x / A) through both pins then has A = span / 2 and sags A (cosh 1 - 1) at the middle
struct HangingChain {
  Scene scene;
  Weave weave;
  RingFrame frame;
  double span = 0.0, A = 0.0;  // m

  explicit HangingChain(int n) {
    scene.weave.type = WeaveType::chain;
    scene.weave.cols = n;
    scene.weave.spacing = 1.0 / std::sinh(1.0);
    PinSpec first, last;
    last.col = n - 1;
    scene.pins = {first, last};
    weave = make_weave(scene.weave, scene.ring);
    frame.resize(n);
    frame.position = weave.rest_position;
    span = (weave.rest_position.col(n - 1) - weave.rest_position.col(0)).norm();
    A = 0.5 * span;
  }
  // every ring lowered `scale` times onto the analytic catenary
  void hang(double scale) {
    const Vec3 middle = 0.5 * (weave.rest_position.col(0) + weave.rest_position.col(size() - 1));
    for (int i = 0; i < size(); ++i) {
      const double x = (weave.rest_position.col(i) - middle).norm();
      frame.position.col(i) = weave.rest_position.col(i);
      frame.position(1, i) -= scale * A * (std::cosh(1.0) - std::cosh(x / A));
    }
  }
  int size() const { return weave.size(); }
};

TEST(Catenary, SagMeasuredAgainstTheAnalyticCatenary) {
  HangingChain chain(21);  // odd: the middle ring sits at the lowest point
  const double length = (chain.size() - 1) * chain.scene.ring.max_link_distance();
  ASSERT_NEAR(2.0 * chain.A * std::sinh(chain.span / (2.0 * chain.A)), length, 1e-12 * length);
  // the straight rest chain has no sag: error 1 (100 %)
  ASSERT_TRUE(catenary_error(chain.scene, chain.weave, chain.frame).has_value());
  EXPECT_NEAR(*catenary_error(chain.scene, chain.weave, chain.frame), 1.0, 1e-12);
  // on the catenary: error 0; half and one and a half times its sag: 50 %
  chain.hang(1.0);
  EXPECT_NEAR(*catenary_error(chain.scene, chain.weave, chain.frame), 0.0, 1e-9);
  chain.hang(0.5);
  EXPECT_NEAR(*catenary_error(chain.scene, chain.weave, chain.frame), 0.5, 1e-9);
  chain.hang(1.5);
  EXPECT_NEAR(*catenary_error(chain.scene, chain.weave, chain.frame), 0.5, 1e-9);
}

TEST(Catenary, OnlyForAChainPinnedAtBothEndsAtEqualHeight) {
  HangingChain one_end(9);
  one_end.scene.pins.pop_back();
  EXPECT_FALSE(catenary_error(one_end.scene, one_end.weave, one_end.frame).has_value());
  HangingChain inner(9);
  inner.scene.pins.back().col = 7;  // not the last ring
  EXPECT_FALSE(catenary_error(inner.scene, inner.weave, inner.frame).has_value());
  HangingChain tilted(9);
  tilted.scene.gravity = Vec3(-9.81, 0.0, 0.0);  // along the chain: one pin above the other
  EXPECT_FALSE(catenary_error(tilted.scene, tilted.weave, tilted.frame).has_value());
  HangingChain taut(9);
  taut.scene.weave.spacing = 1.0;  // span = length: no catenary to hang on
  taut.weave = make_weave(taut.scene.weave, taut.scene.ring);
  EXPECT_FALSE(catenary_error(taut.scene, taut.weave, taut.frame).has_value());
  Layout cloth(sheet("4in1", 4, 4));  // a sheet is not a chain
  cloth.scene.pins = one_end.scene.pins;
  EXPECT_FALSE(catenary_error(cloth.scene, cloth.weave, cloth.frame).has_value());
}

}  // namespace
}  // namespace chainmail
