#include "bench/harness/render_output.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "backends/backend.hpp"
#include "core/scene.hpp"
#if CHAINMAIL_HAVE_RENDER
#include "render/renderer.hpp"
#endif

namespace chainmail {

#if CHAINMAIL_HAVE_RENDER
std::function<void(const SceneRun&, const std::string&)> make_render_writer(
    const std::string& cloth_shader, const std::string& material) {
  render::RenderSettings settings;
  if (!material.empty()) settings.material = material;
  // the textured-cloth baseline shows a chainmail texture unless another shader is asked for
  settings.cloth_shader = cloth_shader.empty() ? "texture" : cloth_shader;
  std::shared_ptr<render::Renderer> renderer;
  try {
    renderer = render::Renderer::create(settings);  // GL context + every shader, checked up front
  } catch (const render::RenderError& e) {
    throw SceneError(std::string("--render: ") + e.what());
  }
  return [renderer](const SceneRun& run, const std::string& folder) {
    std::filesystem::create_directories(folder);
    size_t samples = 0;
    for (const auto& b : run.runs) samples = std::max(samples, b.frames.size());
    // one image per sample: every backend's frame at that sample, side by side, same camera
    for (size_t k = 0; k < samples; ++k) {
      std::vector<render::Panel> panels;
      for (const auto& b : run.runs) {
        if (b.frames.empty()) continue;
        render::Panel panel;
        panel.label = b.name;
        panel.frame = &b.frames[std::min(k, b.frames.size() - 1)];
        const BackendInfo* info = find_backend(b.name);
        panel.as_cloth = info && info->cloth_surface;
        panel.ms_per_step = b.ms_per_step();
        panels.push_back(panel);
      }
      char name[32];
      std::snprintf(name, sizeof name, "/%05zu.png", k);
      render::write_png(renderer->render(run.scene, run.weave, panels), folder + name);
    }
    // a movie of the images when ffmpeg is installed
    if (samples > 1) {
      if (std::system("command -v ffmpeg >/dev/null 2>&1") == 0) {
        const std::string command =
            "ffmpeg -loglevel error -y -framerate 20 -i '" + folder +
            "/%05d.png' -pix_fmt yuv420p -vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' '" + folder +
            "/compare.mp4'";
        if (std::system(command.c_str()) != 0)
          std::fprintf(stderr, "render: ffmpeg failed, no compare.mp4\n");
      } else {
        std::fprintf(stderr,
                     "render: ffmpeg is not installed, so no compare.mp4 (images/ are written)\n");
      }
    }
  };
}
#else
std::function<void(const SceneRun&, const std::string&)> make_render_writer(const std::string&,
                                                                            const std::string&) {
  throw SceneError(
      "--render: this build has no renderer (configured with CHAINMAIL_WITH_RENDER=OFF)");
}
#endif

}  // namespace chainmail
