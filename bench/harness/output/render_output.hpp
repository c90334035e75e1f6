// Drawing sampled frames side by side into images/ (and a movie when ffmpeg exists): a run's own
// frames as it finishes, or a saved run's frames again (`chainmail render`).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "bench/harness/output/frame_stream.hpp"
#include "bench/harness/run/run.hpp"

namespace chainmail {

// how images are drawn
struct ImageSettings {
  int width = 1280, height = 720;            // per panel, pixels
  int samples = 4;                           // multisamples of meshes and ground (0 and 1: none)
  std::string material;                      // ring material ("" = steel)
  std::string cloth_shader;                  // how cloth-surface backends are drawn ("" = texture)
  std::optional<Eigen::Vector3d> view_from;  // automatic framing from here; none: scene's camera
  std::string flag = "--render";             // what messages start with ("": the renderer's own)
};

// one panel: a backend's frames and its label
struct PanelFrames {
  std::string name;
  double ms_per_step = -1.0;  // shown in the label when >= 0
  FrameSequence frames;
};

enum class Video { if_ffmpeg, always, never };

struct ImageOptions {
  bool last_only = false;  // one image, of the last sample, named for its time (t1.000s.png)
  Video video = Video::if_ffmpeg;
  double fps = 20.0;               // of the movie
  bool stop_on_interrupt = false;  // a signal ends the drawing after the current image
};

// draws the panels' frames side by side, one image per sample (NNNNN.png, the same numbering as
// the frames; a panel with fewer frames shows its last), into `folder`; returns the images drawn
using ImageWriter = std::function<int(const Scene&, const Weave&, const std::vector<PanelFrames>&,
                                      const std::string& folder, const ImageOptions&)>;
// creating it checks that GL, the shaders and the settings are usable (SceneError naming
// settings.flag otherwise: exit status 2)
ImageWriter make_image_writer(const ImageSettings& settings);

// whether `ffmpeg` can be run
bool ffmpeg_available();

// the run's side-by-side images from its frame streams (RunOptions::keep_stream), each frame as
// its CSV holds it, so that `chainmail render` redraws the very same pixels from saved frames
// (`cloth_shader`, `material`: empty for the defaults, texture and steel; `last_only`: one image,
// of the last sample)
std::function<void(const SceneRun&, const std::string&)> make_render_writer(
    const std::string& cloth_shader, const std::string& material = "", bool last_only = false);

}  // namespace chainmail
