#include "bench/harness/output/render_output.hpp"

#include <stdlib.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "backends/backend.hpp"
#include "bench/harness/common/data_dir.hpp"
#include "bench/harness/common/interrupt.hpp"
#include "bench/harness/output/frame_stream.hpp"
#include "bench/harness/output/output.hpp"
#include "core/scene.hpp"
#if CHAINMAIL_HAVE_RENDER
#include "render/renderer.hpp"
#endif

namespace chainmail {

bool ffmpeg_available() {
  return std::system("command -v ffmpeg >/dev/null 2>&1") == 0;
}

namespace {

// the images joined into compare.mp4 at `fps` frames per second
void write_movie(const std::string& folder, const ImageOptions& options) {
  if (options.video == Video::never) return;
  if (!ffmpeg_available()) {
    std::fprintf(stderr,
                 "render: ffmpeg is not installed, so no compare.mp4 (images/ are written)\n");
    return;
  }
  char rate[32];
  std::snprintf(rate, sizeof rate, "%g", options.fps);
  const std::string command = std::string("ffmpeg -loglevel error -y -framerate ") + rate +
                              " -i '" + folder +
                              "/%05d.png' -pix_fmt yuv420p -vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' '" +
                              folder + "/compare.mp4'";
  if (std::system(command.c_str()) != 0)
    std::fprintf(stderr, "render: ffmpeg failed, no compare.mp4\n");
}

// the image's file name: its sample number, or its time for the one image of the last sample
std::string image_name(std::size_t k, double t, bool last_only) {
  char name[48];
  if (last_only)
    std::snprintf(name, sizeof name, "/t%.3fs.png", t);
  else
    std::snprintf(name, sizeof name, "/%05zu.png", k);
  return name;
}

}  // namespace

#if CHAINMAIL_HAVE_RENDER
ImageWriter make_image_writer(const ImageSettings& image) {
  // Mesa would keep a shader cache in the user's cache folder: nothing is written but what was
  // asked
  ::setenv("MESA_SHADER_CACHE_DISABLE", "true", /*overwrite=*/0);
  render::RenderSettings settings;
  settings.shader_dir = render_shader_dir();
  settings.width = image.width, settings.height = image.height;
  settings.samples = image.samples;
  if (!image.material.empty()) settings.material = image.material;
  // the textured-cloth baseline shows a chainmail texture unless another shader is asked for
  settings.cloth_shader = image.cloth_shader.empty() ? "texture" : image.cloth_shader;
  settings.view_from = image.view_from;
  std::shared_ptr<render::Renderer> renderer;
  try {
    renderer = render::Renderer::create(settings);  // GL context + every shader, checked up front
  } catch (const render::RenderError& e) {
    throw SceneError(image.flag.empty() ? std::string(e.what()) : image.flag + ": " + e.what());
  }
  return [renderer](const Scene& scene, const Weave& weave, const std::vector<PanelFrames>& panels,
                    const std::string& folder, const ImageOptions& options) {
    std::filesystem::create_directories(folder);
    std::size_t samples = 0;
    for (const PanelFrames& panel : panels) samples = std::max(samples, panel.frames.count);
    std::vector<RingFrame> frames(panels.size());
    int drawn = 0;
    // one image per sample (or the last only): every panel's frame at it, side by side
    for (std::size_t k = options.last_only && samples ? samples - 1 : 0; k < samples; ++k) {
      if (options.stop_on_interrupt && interrupted()) break;
      std::vector<render::Panel> drawn_panels;
      double t = 0.0;
      for (std::size_t p = 0; p < panels.size(); ++p) {
        const FrameSequence& sequence = panels[p].frames;
        if (sequence.count == 0 || !sequence.read(std::min(k, sequence.count - 1), frames[p]))
          continue;
        const BackendInfo* info = find_backend(panels[p].name);
        drawn_panels.push_back(
            {panels[p].name, &frames[p], info && info->cloth_surface, panels[p].ms_per_step});
        t = std::max(t, frames[p].t);
      }
      if (drawn_panels.empty()) continue;
      render::write_png(renderer->render(scene, weave, drawn_panels),
                        folder + image_name(k, t, options.last_only));
      ++drawn;
    }
    if (drawn > 1 && !options.last_only) write_movie(folder, options);
    return drawn;
  };
}
#else
ImageWriter make_image_writer(const ImageSettings& image) {
  throw SceneError((image.flag.empty() ? "render" : image.flag) +
                   ": this build has no renderer (configured with CHAINMAIL_WITH_RENDER=OFF)");
}
#endif

std::function<void(const SceneRun&, const std::string&)> make_render_writer(
    const std::string& cloth_shader, const std::string& material, bool last_only) {
  ImageSettings settings;
  settings.cloth_shader = cloth_shader;
  settings.material = material;
  const ImageWriter draw = make_image_writer(settings);
  return [draw, last_only](const SceneRun& run, const std::string& folder) {
    std::vector<PanelFrames> panels;
    for (const BackendRun& b : run.runs) {
      if (b.stream.empty()) continue;
      auto reader = FrameReader::open(b.stream, run.weave.size());
      if (!reader) continue;
      FrameSequence stream = stream_sequence(std::move(*reader));
      // drawn as saved: every number rounded as the frame CSVs write it
      FrameSequence as_saved{stream.count, [stream](std::size_t k, RingFrame& frame) {
                               if (!stream.read(k, frame)) return false;
                               round_as_csv(frame);
                               return true;
                             }};
      panels.push_back({b.name, b.ms_per_step(), std::move(as_saved)});
    }
    ImageOptions options;
    options.last_only = last_only;
    draw(run.scene, run.weave, panels, folder, options);
  };
}

}  // namespace chainmail
