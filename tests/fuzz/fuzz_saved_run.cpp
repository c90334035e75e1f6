// `chainmail render RUN_DIR`'s loader: the input is summary.json, metrics.csv and one frame CSV
// (frames/<first backend>/00000.csv), separated by NUL bytes. A folder chainmail could not have
// written must be a UsageError or SceneError naming it (exit 2); anything else is a bug.
#include "bench/harness/common/usage_error.hpp"
#include "bench/harness/output/saved_run.hpp"
#include "core/scene.hpp"
#include "tests/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace chainmail;
  const std::vector<std::string> input = fuzz::parts(data, size, 3);
  const std::string run = fuzz::scratch() + "/run";
  fuzz::write(run + "/summary.json", input[0]);
  if (input.size() > 1) fuzz::write(run + "/metrics.csv", input[1]);
  // the frame goes to the backend the metrics name first (the text before the first comma of
  // the second line), so that the loader reads it
  if (input.size() > 2) {
    const std::string& metrics = input[1];
    const std::size_t line = metrics.find('\n'), comma = metrics.find(',', line + 1);
    std::string backend = line == std::string::npos || comma == std::string::npos
                              ? "plausible"
                              : metrics.substr(line + 1, comma - line - 1);
    if (backend.empty() || backend.find('/') != std::string::npos || backend[0] == '.')
      backend = "plausible";
    fuzz::write(run + "/frames/" + backend + "/00000.csv", input[2]);
  }
  try {
    const SavedRun saved = read_saved_run(run);
    RingFrame frame;
    for (const SavedBackend& b : saved.backends) {
      const FrameSequence frames = saved.frames(b);
      for (std::size_t k = 0; k < frames.count && k < 4; ++k) frames.read(k, frame);
    }
  } catch (const UsageError&) {
  } catch (const SceneError&) {
  }
  return 0;
}
