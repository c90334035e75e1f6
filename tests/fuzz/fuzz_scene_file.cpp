// The scene-file parser with --set overrides: the input is a scene file, then overrides
// ("key=value"), separated by NUL bytes. Bad input must be a SceneError (exit 2 on the command
// line); anything else escaping is a bug. A scene that loads must write back to a document that
// loads to the same scene.
#include "core/scene.hpp"
#include "scene_file/scene_file.hpp"
#include "tests/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace chainmail;
  const std::vector<std::string> input = fuzz::parts(data, size, 9);
  const std::string path = fuzz::scratch() + "/scene.json";
  fuzz::write(path, input[0]);
  const std::vector<std::string> overrides(input.begin() + 1, input.end());
  Scene scene;
  try {
    scene = load_scene_file(path, overrides);
  } catch (const SceneError&) {
    return 0;
  }
  const nlohmann::json written = scene_to_json(scene);
  const Scene again = scene_from_json(written, "written back");
  if (scene_to_json(again) != written) __builtin_trap();  // writing back changed the scene
  return 0;
}
