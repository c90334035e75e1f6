// The one fixture of the backend tests: a scene, its rest layout and a backend of the registry
// reset on them, stepped at its dt knob; and skipping what this binary was built without.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <utility>

#include "backends/backend.hpp"
#include "core/frame.hpp"
#include "core/geometry.hpp"
#include "core/scene.hpp"
#include "core/weave.hpp"
#include "scene_file/scene_file.hpp"

namespace chainmail::test {

// a scene, its rest layout, the resolved knobs and a fresh backend reset on them
struct BackendSim {
  Scene scene;
  Weave weave;
  Knobs knobs;
  std::unique_ptr<Backend> backend;
  RingFrame frame;  // the latest: read after reset and after every steps() / advance()
  StepStatus status = StepStatus::ok;  // the last step's

  BackendSim(const std::string& name, const Scene& s)
      : scene(s), weave(make_weave(s.weave, s.ring)) {
    const BackendInfo* info = find_backend(name);
    if (!info) throw std::runtime_error("backend '" + name + "' is not built into this binary");
    knobs = resolve_knobs(scene, *info);
    backend = info->create();
    backend->reset(scene, weave, knobs);
    backend->frame(frame);
  }
  BackendSim(const std::string& name, const nlohmann::json& document)
      : BackendSim(name, scene_from_json(document, "test")) {}

  double dt() const { return knobs.at("dt"); }
  // `count` steps of the dt knob, then the frame
  void steps(long long count) {
    for (long long k = 0; k < count; ++k) status = backend->step(dt());
    backend->frame(frame);
  }
  // the whole number of steps nearest to `seconds`, then the frame
  void advance(double seconds) { steps(std::llround(seconds / dt())); }
  // the reset again, on the same scene, layout and knobs
  void restart() {
    backend->reset(scene, weave, knobs);
    backend->frame(frame);
  }
  const StageProfile& profile() const { return backend->profile(); }
  Circle circle(int ring) const {
    return ring_circle(frame.position.col(ring), frame.quat(ring), scene.ring.centre_radius);
  }
};

// marks the running test skipped, saying why, when `backend` is not built into this binary; from
// a fixture's SetUp that keeps the test body from running
inline void skip_unless_built(const std::string& backend) {
  if (!backend_built(backend)) {
    GTEST_SKIP() << "backend " << backend << " is not built into this binary";
  }
}

// a fixture for the tests of one backend, skipped when it is not built
class BackendTest : public ::testing::Test {
 protected:
  explicit BackendTest(std::string backend) : backend_(std::move(backend)) {}
  void SetUp() override { skip_unless_built(backend_); }
  BackendSim sim(const nlohmann::json& document) const { return BackendSim(backend_, document); }
  BackendSim sim(const Scene& scene) const { return BackendSim(backend_, scene); }

 private:
  std::string backend_;
};

}  // namespace chainmail::test
