// The renderer's vocabulary: its settings, panels, images, statistics and error, apart from the
// Renderer itself so that the pieces it is built from (GL context, shaders, targets, images) can
// use them without including the renderer.
#pragma once

#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/frame.hpp"
#include "render/scene_view.hpp"

namespace chainmail::render {

struct RenderSettings {
  int width = 1280, height = 720;  // per panel, pixels
  int samples = 4;  // MSAA samples for meshes, ground and colliders (0/1 = off); ray-cast rings
                    // are antialiased by their own coverage either way
  bool lod = true;  // pick each ring's level from its size on screen; false: the finest mesh
  double lod_scale = 1.0;  // on-screen size is scaled by this before the level is picked: below 1
                           // coarser levels sooner (0: every ring ray-cast), above 1 later
  std::string context = "auto";    // auto | osmesa | egl (auto tries OSMesa, then EGL)
  std::string shader_dir;          // empty: beside the executable, then $CHAINMAIL_SHADER_DIR
  std::string material = "steel";  // steel | gold | copper | brass | bronze | silver | titanium
  std::string cloth_shader = "blinn_phong";  // blinn_phong | texture | bump | displacement | mirror
  bool live_blur = false;  // blur the reflection per fragment (13 taps per axis, slow on
                           // llvmpipe) instead of once into a prefiltered cubemap at start-up
  bool labels = true;      // label strip at the top of every panel
  // automatic framing from this direction (towards the eye) instead of the scene's camera
  std::optional<Eigen::Vector3d> view_from;

  // shared libraries to load; empty: the usual sonames (libOSMesa.so.8, ... / libEGL.so.1)
  std::string osmesa_library;
  std::string egl_library;
};

struct Panel {
  std::string label;  // e.g. the backend name
  const RingFrame* frame = nullptr;
  bool as_cloth = false;      // draw the frame as a cloth mesh over the weave grid
  double ms_per_step = -1.0;  // shown in the label when >= 0
};

struct Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgba;  // width * height * 4, row 0 = top
};

struct FrameStats {
  double ms = 0;                          // wall time of the last render() call
  int instances = 0;                      // rings drawn (after frustum culling), all panels
  std::array<int, kLodLevels> per_lod{};  // of those, per level of detail (0 = finest; the
                                          // last is the ray-cast level)
};

class RenderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace chainmail::render
