// `chainmail render RUN_DIR`: a saved run's frames drawn (and exported) again, at another size,
// sampling, camera, material or frame rate, without simulating.
#pragma once

#include <string>
#include <vector>

namespace chainmail {

struct RenderCommand {
  std::string run_dir;                // a `chainmail run` folder with frames/ (run --frames)
  std::vector<std::string> backends;  // panels, in this order; empty: every backend with frames
  std::string out_dir;                // empty: results/<scene name>/render
  bool force = false;                 // replace a foreign empty folder at out_dir
  std::string size = "1280x720";      // per panel, WxH pixels
  int samples = 4;                    // multisamples (0, 1: none)
  std::string camera = "scene";       // a named view, or POSITION:TARGET[:FOV_DEG]
  double fps = 20.0;                  // of the movie
  bool fps_given = false;
  bool video = false;                // images/compare.mp4 (needs ffmpeg)
  bool images = true;                // false: exports only, no GL needed
  std::string material;              // ring material ("" = steel)
  std::string shader;                // cloth shader ("" = texture)
  std::vector<std::string> exports;  // gltf and/or npz: export/<backend>.glb|.npz
};
int render_command(const RenderCommand& command);

// the named views of --camera: scene (the run's own camera), auto, front, side, top
std::vector<std::string> camera_view_names();

}  // namespace chainmail
