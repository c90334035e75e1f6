// The one rendering path: every backend's RingFrame goes through the same instanced torus renderer,
// so that differences between panels are differences in physics, never in drawing.
// Headless OpenGL 3.3 core through OSMesa or EGL surfaceless; all drawing goes into an FBO that is
// read back with glReadPixels.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/frame.hpp"
#include "core/scene.hpp"
#include "core/weave.hpp"
#include "render/image.hpp"  // write_png
#include "render/scene_view.hpp"
#include "render/settings.hpp"  // material_names, cloth_shader_names
#include "render/types.hpp"

namespace chainmail::render {

class Renderer {
 public:
  // creates the GL context, compiles every shader and builds the environment map;
  // throws RenderError (no GL, missing or broken shader, bad setting)
  static std::unique_ptr<Renderer> create(const RenderSettings& settings);
  virtual ~Renderer();

  // one image of panels.size() panels side by side (same camera), each settings.width wide
  virtual Image render(const Scene& scene, const Weave& weave,
                       const std::vector<Panel>& panels) = 0;
  virtual const FrameStats& last_stats() const = 0;
  virtual std::string context_name() const = 0;  // "osmesa" or "egl"
  virtual std::string gl_renderer() const = 0;   // GL_RENDERER / GL_VERSION, for reports
};

}  // namespace chainmail::render
