// chainmail.run and chainmail.sweep: the command line's `run` and `sweep` (bench/harness), with a
// scene loaded in Python; results come back as Python objects.
#include <signal.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <optional>

#include <pybind11/stl.h>

#include "bench/harness/commands/commands.hpp"
#include "bench/harness/common/interrupt.hpp"
#include "bench/harness/suites/sweep.hpp"
#include "python/bindings.hpp"

namespace chainmail::python {
namespace fs = std::filesystem;
namespace {

// the `chainmail` binary that runs sweep points (set by the package's __init__.py)
std::string g_executable;

// while a command runs without the GIL, Ctrl-C and SIGTERM go to the harness's handlers (the
// command stops at the next step and writes what finished, as on the command line); Python's
// own are back afterwards, and an interrupted command raises KeyboardInterrupt
class HarnessSignals {
 public:
  HarnessSignals() {
    sigaction(SIGINT, nullptr, &old_int_);
    sigaction(SIGTERM, nullptr, &old_term_);
    set_interrupted(false);
    install_interrupt_handlers();
  }
  ~HarnessSignals() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  // raises KeyboardInterrupt when a signal stopped the command
  static void raise_if_interrupted(int status) {
    if (status != kExitInterrupted && !interrupted()) return;
    set_interrupted(false);
    PyErr_SetNone(PyExc_KeyboardInterrupt);
    throw py::error_already_set();
  }

 private:
  struct sigaction old_int_ {
  }, old_term_{};
};

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

// a folder of our own for a run the caller did not ask to keep
struct TemporaryFolder {
  std::string path;
  TemporaryFolder() {
    std::string name = (fs::temp_directory_path() / "chainmail-python.XXXXXX").string();
    if (!::mkdtemp(name.data())) throw std::runtime_error("cannot create a temporary folder");
    path = name;
  }
  ~TemporaryFolder() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
};

// runs a harness command with the GIL released and Ctrl-C handled as on the command line; an
// interrupted command raises KeyboardInterrupt once the GIL is back
template <typename Command>
void without_the_gil(Command&& command) {
  int status = 0;
  {
    HarnessSignals signals;
    py::gil_scoped_release release;
    status = command();
  }
  HarnessSignals::raise_if_interrupted(status);
}

py::object run(const PyScene& scene, const std::vector<std::string>& backends,
               const std::optional<std::string>& out, const std::string& reference,
               const std::string& cache, bool progress, int threads) {
  for (const std::string& name : backends) check_text("backends", name);
  if (out) check_text("out", *out);
  check_text("reference", reference);
  check_text("cache", cache);
  std::optional<TemporaryFolder> temporary;
  if (!out) temporary.emplace();
  RunCommand command;
  command.scene_file = scene.path;
  command.overrides = scene.overrides;
  command.backends = backends;
  command.out_dir = out ? *out : temporary->path + "/run";
  command.reference = reference;
  command.cache_dir = cache;
  command.progress = progress;
  command.threads = checked_threads(threads);
  without_the_gil([&] { return run_command(command); });
  return to_python(read_json(command.out_dir + "/summary.json"));
}

std::string sweep(const PyScene& scene, const std::vector<std::string>& vary,
                  const std::vector<std::string>& backends, const std::optional<std::string>& out,
                  int jobs, const std::string& cache, bool progress, int threads) {
  for (const std::string& text : vary) check_text("vary", text);
  for (const std::string& name : backends) check_text("backends", name);
  if (out) check_text("out", *out);
  check_text("cache", cache);
  if (jobs < 1 || jobs > 256)
    throw py::value_error("jobs: " + std::to_string(jobs) + " is outside 1 to 256");
  SweepCommand command;
  command.scene_file = scene.path;
  command.overrides = scene.overrides;
  command.vary = vary;
  command.backends = backends;
  command.out_dir = out ? *out : "results/" + scene.scene.name + "/sweep";
  command.jobs = jobs;
  command.cache_dir = cache;
  command.progress = progress;
  command.threads = checked_threads(threads);
  command.executable = g_executable;
  without_the_gil([&] { return sweep_command(command); });
  return command.out_dir;
}

}  // namespace

void add_commands(py::module_& m) {
  m.def("run", &run, py::arg("scene"), py::arg("backends") = std::vector<std::string>{},
        py::arg("out") = py::none(), py::arg("reference") = "", py::arg("cache") = "",
        py::arg("progress") = false, py::arg("threads") = 0,
        "`chainmail run`: the scene through the backends (default: the scene's); returns the "
        "summary (summary.json) as a dict. out: keep the run folder there (default: none kept); "
        "threads: as --threads (0: every hardware thread)");
  m.def("_sweep", &sweep, py::arg("scene"), py::arg("vary"),
        py::arg("backends") = std::vector<std::string>{}, py::arg("out") = py::none(),
        py::arg("jobs") = 1, py::arg("cache") = "", py::arg("progress") = false,
        py::arg("threads") = 0);
  m.def("_set_executable", [](const std::string& path) { g_executable = path; });
}

}  // namespace chainmail::python
