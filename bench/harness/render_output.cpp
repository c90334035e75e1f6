#include "bench/harness/render_output.hpp"

#include "core/scene.hpp"

namespace chainmail {

std::function<void(const SceneRun&, const std::string&)> make_render_writer(const std::string&) {
  throw SceneError("--render: this build has no renderer yet");
}

}  // namespace chainmail
