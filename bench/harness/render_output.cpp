#include "bench/harness/render_output.hpp"

#include <stdlib.h>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "backends/backend.hpp"
#include "bench/harness/data_dir.hpp"
#include "bench/harness/frame_stream.hpp"
#include "core/scene.hpp"
#if CHAINMAIL_HAVE_RENDER
#include "render/renderer.hpp"
#endif

namespace chainmail {

#if CHAINMAIL_HAVE_RENDER
std::function<void(const SceneRun&, const std::string&)> make_render_writer(
    const std::string& cloth_shader, const std::string& material, bool last_only) {
  // Mesa would keep a shader cache in the user's cache folder: nothing is written but what was
  // asked
  ::setenv("MESA_SHADER_CACHE_DISABLE", "true", /*overwrite=*/0);
  render::RenderSettings settings;
  settings.shader_dir = render_shader_dir();
  if (!material.empty()) settings.material = material;
  // the textured-cloth baseline shows a chainmail texture unless another shader is asked for
  settings.cloth_shader = cloth_shader.empty() ? "texture" : cloth_shader;
  std::shared_ptr<render::Renderer> renderer;
  try {
    renderer = render::Renderer::create(settings);  // GL context + every shader, checked up front
  } catch (const render::RenderError& e) {
    throw SceneError(std::string("--render: ") + e.what());
  }
  return [renderer, last_only](const SceneRun& run, const std::string& folder) {
    std::filesystem::create_directories(folder);
    // every backend's frames, read back one sample at a time from its stream
    struct Source {
      const BackendRun* run;
      FrameReader reader;
      RingFrame frame;
    };
    std::vector<Source> sources;
    size_t samples = 0;
    for (const auto& b : run.runs) {
      if (b.stream.empty()) continue;
      auto reader = FrameReader::open(b.stream, run.weave.size());
      if (!reader) continue;
      samples = std::max(samples, reader->count());
      sources.push_back({&b, std::move(*reader), RingFrame()});
    }
    // one image per sample (or the last only): every backend's frame at it, side by side
    for (size_t k = last_only && samples ? samples - 1 : 0; k < samples; ++k) {
      std::vector<render::Panel> panels;
      for (auto& source : sources) {
        if (!source.reader.read(std::min(k, source.reader.count() - 1), source.frame)) continue;
        render::Panel panel;
        panel.label = source.run->name;
        panel.frame = &source.frame;
        const BackendInfo* info = find_backend(source.run->name);
        panel.as_cloth = info && info->cloth_surface;
        panel.ms_per_step = source.run->ms_per_step();
        panels.push_back(panel);
      }
      char name[32];
      std::snprintf(name, sizeof name, "/%05zu.png", k);
      render::write_png(renderer->render(run.scene, run.weave, panels), folder + name);
    }
    // a movie of the images when ffmpeg is installed
    if (samples > 1 && !last_only) {
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
                                                                            const std::string&,
                                                                            bool) {
  throw SceneError(
      "--render: this build has no renderer (configured with CHAINMAIL_WITH_RENDER=OFF)");
}
#endif

}  // namespace chainmail
