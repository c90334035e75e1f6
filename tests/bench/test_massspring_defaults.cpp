// The massspring backend at its own default knobs, run by the harness: a fair game cloth that
// sags into a V when hung by two corners and stays stable (verdict and settled) on small curtains
// with no scene override, where the document's stiff plate at one substep does not.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "backends/backend.hpp"
#include "bench/harness/run/run.hpp"
#include "core/weave.hpp"
#include "scene_file/scene_file.hpp"

namespace chainmail {
namespace {

RunOptions quiet() {
  RunOptions options;
  options.progress = false;
  return options;
}

// the bench's curtain (bench/scenes/curtain.json) at n x n rings, pinned as given
Scene sheet(int n, const nlohmann::json& pins, double duration, const nlohmann::json& knobs) {
  const nlohmann::json document = {
      {"name", "massspring_sheet"},
      {"ring",
       {{"wire_diameter", 0.0016},
        {"inner_diameter", 0.008},
        {"density", 7850},
        {"friction", 0.3}}},
      {"weave", {{"type", "4in1"}, {"rows", n}, {"cols", n}, {"plane", "xy"}}},
      {"pins", pins},
      {"duration", duration},
      {"sample_interval", 0.05},
      {"features", {{"self_contact", true}}},
      {"reference", "massspring"},
      {"backends", {{"massspring", knobs}}}};
  return scene_from_json(document, "massspring_sheet.json");
}

const nlohmann::json kTopEdge = {{{"edge", "top"}}};
const nlohmann::json kTwoCorners = {{{"corner", "top_left"}}, {{"corner", "top_right"}}};

BackendRun run(const Scene& scene) {
  return run_backend(scene, make_weave(scene.weave, scene.ring), "massspring", quiet());
}

TEST(MassSpringDefaults, CurtainsAreStableAndSettleWithNoOverride) {
  for (const int n : {4, 8, 16}) {
    SCOPED_TRACE(n);
    const BackendRun r = run(sheet(n, kTopEdge, 1.0, nlohmann::json::object()));
    EXPECT_TRUE(r.stable) << to_string(r.verdict);
    ASSERT_TRUE(r.settled.has_value());
    EXPECT_TRUE(*r.settled);
  }
  // the document's stiff plate (5000 N/m on 0.48 g rings) at one substep of 1/2700 s is not
  const BackendRun stiff =
      run(sheet(8, kTopEdge, 1.0,
                {{"ks", 5000.0}, {"shear_ks", 5000.0}, {"bend_ks", 1000.0}, {"substeps", 1}}));
  EXPECT_FALSE(stiff.stable);
}

// how far the middle of the top row hangs below the line between the top row's two ends, m
// (the row of the pinned corners)
double top_row_sag(const RingFrame& frame, const Scene& scene, const Weave& weave) {
  const int row = weave.row_col[resolve_pins(scene, weave).front()][0];
  std::vector<int> top;
  for (int ring = 0; ring < weave.size(); ++ring) {
    if (weave.row_col[ring][0] == row) top.push_back(ring);
  }
  const Vec3 a = frame.position.col(top.front()), b = frame.position.col(top.back());
  const Vec3 middle = frame.position.col(top[top.size() / 2]);
  return 0.5 * (a.y() + b.y()) - middle.y();
}

TEST(MassSpringDefaults, ASheetHungByTwoCornersSagsIntoAV) {
  const Scene scene = sheet(12, kTwoCorners, 1.5, nlohmann::json::object());
  const Weave weave = make_weave(scene.weave, scene.ring);
  const BackendRun cloth = run(scene);
  ASSERT_TRUE(cloth.stable) << to_string(cloth.verdict);
  // the pins' distance is the rest row's length; a V whose middle hangs a tenth of it below
  const std::vector<int> pins = resolve_pins(scene, weave);
  ASSERT_EQ(pins.size(), 2u);
  const double width = (weave.rest_position.col(pins[1]) - weave.rest_position.col(pins[0])).norm();
  const double sag = top_row_sag(cloth.final_frame, scene, weave);
  EXPECT_GT(sag, 0.1 * width);
  // the document's stiff plate hangs its top row almost straight
  const Scene plate_scene =
      sheet(12, kTwoCorners, 1.5,
            {{"ks", 5000.0}, {"shear_ks", 5000.0}, {"bend_ks", 1000.0}, {"substeps", 10}});
  const BackendRun plate = run(plate_scene);
  ASSERT_TRUE(plate.stable) << to_string(plate.verdict);
  EXPECT_LT(top_row_sag(plate.final_frame, plate_scene, weave), 0.1 * sag);
}

}  // namespace
}  // namespace chainmail
