// The stability suite's cases: scene files that load in both modes, reduced in quick mode.
#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>

#include "backends/backend.hpp"
#include "bench/harness/run/budget.hpp"
#include "bench/harness/suites/stability.hpp"
#include "core/weave.hpp"

namespace chainmail {
namespace {

const StabilityCase& case_in(const std::string& file) {
  for (const StabilityCase& c : stability_cases()) {
    if (c.file == file) return c;
  }
  throw std::runtime_error("no stability case " + file);
}

TEST(StabilityCases, EveryCaseIsASceneFileThatQuickModeShrinks) {
  ASSERT_GE(stability_cases().size(), 11u);
  for (const StabilityCase& c : stability_cases()) {
    SCOPED_TRACE(c.file);
    const Scene full = load_stability_case(c, false);
    const Scene quick = load_stability_case(c, true);
    EXPECT_EQ(full.name + ".json", c.file);  // tables name a case by its scene
    EXPECT_EQ(quick.name, full.name);
    EXPECT_FALSE(full.description.empty());  // the case list under the table
    EXPECT_LT(ring_count(quick), ring_count(full));
    EXPECT_LE(quick.duration, full.duration);
    const Weave weave = make_weave(quick.weave, quick.ring);
    EXPECT_EQ(weave.size(), ring_count(quick));
    EXPECT_GE(c.bisection_steps, 1);
  }
}

TEST(StabilityCases, TheHeavyRingHangsAtTheMiddleOfTheBottomRowInBothModes) {
  for (bool quick : {false, true}) {
    const Scene scene = load_stability_case(case_in("heavy_weight.json"), quick);
    ASSERT_EQ(scene.loads.size(), 1u);
    EXPECT_EQ(scene.loads[0].row, scene.weave.rows - 1);
    EXPECT_EQ(scene.loads[0].col, scene.weave.cols / 2);
    EXPECT_EQ(scene.loads[0].mass_factor, 100.0);
  }
}

TEST(StabilityCases, LargeDtIsTenTimesEachBackendsDefault) {
  const Scene scene = load_stability_case(case_in("large_dt.json"), false);
  for (const BackendInfo& info : backend_registry()) {
    for (const KnobSpec& knob : info.knobs) {
      if (knob.name != "dt") continue;
      EXPECT_EQ(resolve_knobs(scene, info).at("dt"), std::min(knob.max, 10.0 * knob.default_value))
          << info.name;
    }
  }
}

TEST(StabilityCases, TheSpringStudyRunsMassspringOnlyOverFourDecades) {
  std::vector<double> ks;
  for (const StabilityCase& c : stability_cases()) {
    if (c.only != std::vector<std::string>{"massspring"}) continue;
    const Scene scene = load_stability_case(c, false);
    const Knobs knobs = resolve_knobs(scene, *find_backend("massspring"));
    EXPECT_EQ(knobs.at("shear_ks"), knobs.at("ks")) << c.file;
    EXPECT_EQ(knobs.at("bend_ks"), knobs.at("ks") / 5.0) << c.file;
    ks.push_back(knobs.at("ks"));
  }
  EXPECT_EQ(ks, (std::vector<double>{500.0, 5000.0, 50000.0, 500000.0}));
}

}  // namespace
}  // namespace chainmail
