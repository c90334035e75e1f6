// The plausible model measured against physics: rest, free fall, settling, convergence, contact
// with colliders and the catenary, each at the model's default settings.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/plausible.hpp"

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
      const double turn =
          quat_of(before, i).angularDistance(quat_of(sim.state().orientation, i));
      if (turn > worst) worst = turn, worst_ring = i;
    }
  }
  std::printf("sheet at rest: largest turn %.4g deg per step (ring %d)\n",
              worst * 180.0 / std::numbers::pi, worst_ring);
  EXPECT_LT(worst, 0.1 * std::numbers::pi / 180.0) << "ring " << worst_ring;
}

}  // namespace
}  // namespace chainmail
