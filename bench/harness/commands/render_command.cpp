#include "bench/harness/commands/render_command.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <regex>

#include "bench/harness/commands/commands.hpp"
#include "bench/harness/common/interrupt.hpp"
#include "bench/harness/common/usage_error.hpp"
#include "bench/harness/output/export.hpp"
#include "bench/harness/output/output_folder.hpp"
#include "bench/harness/output/render_output.hpp"
#include "bench/harness/output/saved_run.hpp"

namespace chainmail {
namespace {

// --camera NAME: automatic framing from a direction (towards the eye), or the run's own camera
struct NamedView {
  const char* name;
  std::optional<Vec3> from;  // none: the scene's camera
};
const NamedView kViews[] = {{"scene", std::nullopt},
                            {"auto", Vec3(0.0, 0.6, 1.0)},
                            {"front", Vec3(0.0, 0.15, 1.0)},
                            {"side", Vec3(1.0, 0.15, 0.0)},
                            {"top", Vec3(0.0, 1.0, 0.0)}};

// "x,y,z" as three finite numbers
bool parse_vector(const std::string& text, Vec3& out) {
  std::smatch m;
  static const std::regex three(R"(^([^,]+),([^,]+),([^,]+)$)");
  if (!std::regex_match(text, m, three)) return false;
  for (int k = 0; k < 3; ++k) {
    const std::string cell = m[k + 1].str();
    char* end = nullptr;
    errno = 0;
    out[k] = std::strtod(cell.c_str(), &end);
    if (end != cell.c_str() + cell.size() || errno != 0 || !std::isfinite(out[k])) return false;
  }
  return true;
}

// --camera applied to the scene (a fixed camera) or to the image settings (a framing direction)
void apply_camera(const std::string& text, Scene& scene, ImageSettings& image) {
  for (const NamedView& view : kViews) {
    if (text == view.name) {
      image.view_from = view.from;
      return;
    }
  }
  std::smatch m;
  static const std::regex fixed(R"(^([^:]+):([^:]+)(?::([^:]+))?$)");
  Vec3 position, target;
  const std::string names = "--camera '" + text + "': ";
  if (!std::regex_match(text, m, fixed) || !parse_vector(m[1].str(), position) ||
      !parse_vector(m[2].str(), target)) {
    std::string known;
    for (const NamedView& view : kViews)
      known += std::string(known.empty() ? "" : ", ") + view.name;
    throw UsageError(names + "expected X,Y,Z:X,Y,Z[:FOV_DEG] (position, target, m) or " + known);
  }
  double fov = scene.camera.fov_deg;
  if (m[3].matched) {
    const std::string field = m[3].str();  // kept: strtod's end points into it
    char* end = nullptr;
    fov = std::strtod(field.c_str(), &end);
    if (*end != '\0' || !(fov >= 1.0 && fov <= 170.0))
      throw UsageError(names + "field of view must be in [1, 170] degrees");
  }
  if ((position - target).norm() == 0.0) throw UsageError(names + "position equals target");
  scene.camera = {false, position, target, fov};
}

// --size WxH, each in [16, 8192]
void apply_size(const std::string& text, ImageSettings& image) {
  std::smatch m;
  static const std::regex size(R"(^([0-9]{1,5})x([0-9]{1,5})$)");
  if (std::regex_match(text, m, size)) {
    image.width = std::stoi(m[1].str()), image.height = std::stoi(m[2].str());
    if (image.width >= 16 && image.height >= 16 && image.width <= 8192 && image.height <= 8192)
      return;
  }
  throw UsageError("--size '" + text + "': expected WxH, each 16 to 8192 pixels (e.g. 1920x1080)");
}

// the panels asked for (each a backend of the run with saved frames), or every one with frames
std::vector<const SavedBackend*> chosen_backends(const SavedRun& run,
                                                 const std::vector<std::string>& asked) {
  std::vector<const SavedBackend*> chosen;
  std::string with_frames;
  for (const SavedBackend& b : run.backends) {
    if (b.frames == 0) continue;
    with_frames += (with_frames.empty() ? "" : ", ") + b.name;
    if (asked.empty()) chosen.push_back(&b);
  }
  if (with_frames.empty()) {
    throw UsageError(run.path +
                     ": no saved frames (frames/<backend>/00000.csv): run it with "
                     "--frames to draw it again");
  }
  for (const std::string& name : asked) {
    const auto it = std::find_if(run.backends.begin(), run.backends.end(),
                                 [&](const SavedBackend& b) { return b.name == name; });
    if (it == run.backends.end() || it->frames == 0)
      throw UsageError("--backends: " + name + " has no saved frames in " + run.path +
                       " (with frames: " + with_frames + ")");
    if (std::find(chosen.begin(), chosen.end(), &*it) == chosen.end()) chosen.push_back(&*it);
  }
  return chosen;
}

// every flag that is not about the run folder, checked before anything is read or drawn
void check_flags(const RenderCommand& command) {
  if (command.fps_given && !command.video) throw UsageError("--fps: only with --video");
  if (!(command.fps > 0.0 && command.fps <= 240.0))
    throw UsageError("--fps: must be in (0, 240] frames per second");
  if (command.video && !command.images) throw UsageError("--video: not with --no-images");
  if (!command.images && command.exports.empty())
    throw UsageError("--no-images: nothing to write without --export");
  if (command.video && !ffmpeg_available())
    throw UsageError("--video: ffmpeg is not installed (apt-get install ffmpeg)");
}

}  // namespace

std::vector<std::string> camera_view_names() {
  std::vector<std::string> names;
  for (const NamedView& view : kViews) names.emplace_back(view.name);
  return names;
}

int render_command(const RenderCommand& command) {
  // everything that can be bad input is checked before anything is drawn or written
  check_flags(command);
  const std::vector<ExportFormat> exports = parse_export_formats(command.exports);
  SavedRun run = read_saved_run(command.run_dir);
  const std::vector<const SavedBackend*> chosen = chosen_backends(run, command.backends);
  ImageSettings image;
  image.flag = "";  // the renderer's messages name it already
  image.samples = command.samples;
  image.material = command.material;
  image.cloth_shader = command.shader;
  apply_size(command.size, image);
  apply_camera(command.camera, run.scene, image);
  std::vector<PanelFrames> panels;
  RingFrame probe;
  for (const SavedBackend* b : chosen) {
    panels.push_back({b->name, b->ms_per_step, run.frames(*b)});
    panels.back().frames.read(0, probe);  // the first frame must parse
  }
  const ImageWriter draw = command.images ? make_image_writer(image) : ImageWriter();

  const std::string path =
      command.out_dir.empty() ? "results/" + run.scene.name + "/render" : command.out_dir;
  OutputFolder folder = OutputFolder::claim(path, "render", command.force);
  int images = 0;
  if (draw) {
    ImageOptions options;
    options.video = command.video ? Video::always : Video::never;
    options.fps = command.fps;
    options.stop_on_interrupt = true;
    images = draw(run.scene, run.weave, panels, folder.staging() + "/images", options);
  }
  for (const PanelFrames& panel : panels) {
    if (interrupted()) break;
    write_exports({run.scene, run.weave, panel.name}, panel.frames, exports,
                  folder.staging() + "/export");
  }
  folder.commit();
  std::fprintf(stderr, "wrote %s (%d images%s)%s\n", path.c_str(), images,
               exports.empty() ? "" : ", exports", interrupted() ? " (interrupted)" : "");
  return interrupted() ? kExitInterrupted : kExitOk;
}

}  // namespace chainmail
