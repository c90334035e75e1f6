// A backend opened for a scene: the one sequence every runner of a model follows (the command's
// runs and the Python module's Simulation), so that both step the same model from the same state.
#pragma once

#include <memory>

#include "backends/backend.hpp"

namespace chainmail {

struct OpenedBackend {
  std::unique_ptr<Backend> model;  // reset to the scene, ready for its first step
  Knobs knobs;                     // the scene's knobs for it over the defaults
};

// `info`'s knobs resolved from `scene` (SceneError naming a bad one), then a model created, given
// `threads` threads (at least 1) and reset to `weave`, the scene's rest layout
OpenedBackend open_backend(const Scene& scene, const Weave& weave, const BackendInfo& info,
                           int threads);

}  // namespace chainmail
