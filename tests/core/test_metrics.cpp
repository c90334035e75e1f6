// Metrics on hand-made frames: what each count means, checked against cases whose answer is known.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "core/metrics.hpp"
#include "core/scene.hpp"
#include "core/weave.hpp"

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

}  // namespace
}  // namespace chainmail
