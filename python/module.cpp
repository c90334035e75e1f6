// The extension module chainmail._chainmail: scenes, the backend registry, errors; the simulation
// and the commands come from simulation.cpp and commands.cpp.
#include <pybind11/stl.h>

#include "backends/backend.hpp"
#include "bench/harness/commands/info_commands.hpp"
#include "bench/harness/common/usage_error.hpp"
#include "bench/harness/common/version.hpp"
#include "bench/harness/output/output_error.hpp"
#include "python/bindings.hpp"
#include "scene_file/scene_file.hpp"

namespace chainmail::python {

void check_text(const std::string& argument, const std::string& value) {
  if (value.find('\0') != std::string::npos)
    throw py::value_error(argument + ": holds a NUL byte, which no path or name may hold");
}

int checked_threads(int threads) {
  if (threads < 0 || threads > 4096) {
    throw py::value_error("threads: " + std::to_string(threads) +
                          " is outside 0 to 4096 (0: every hardware thread)");
  }
  return threads;
}

std::vector<std::string> override_texts(const py::dict& overrides) {
  const py::object dumps = py::module_::import("json").attr("dumps");
  std::vector<std::string> texts;
  for (const auto& [key, value] : overrides) {
    if (!py::isinstance<py::str>(key)) {
      throw py::value_error("overrides: key " + py::repr(key).cast<std::string>() +
                            " is not a text (a dotted scene key)");
    }
    const std::string name = py::str(key).cast<std::string>();
    check_text("overrides", name);
    std::string text;
    try {
      text = dumps(value, py::arg("allow_nan") = false).cast<std::string>();
    } catch (const py::error_already_set& e) {
      // NaN, infinity, or an object JSON cannot hold: refused naming the key, as --set would be
      throw py::value_error("overrides: key '" + name +
                            "': " + py::repr(value).cast<std::string>() + " is not a JSON value");
    }
    texts.push_back(name + "=" + text);
  }
  return texts;
}

py::object to_python(const nlohmann::json& value) {
  return py::module_::import("json").attr("loads")(value.dump());
}

namespace {

PyScene load_scene(const std::string& path, const py::dict& overrides) {
  check_text("path", path);
  PyScene s{path, override_texts(overrides), {}};
  s.scene = load_scene_file(path, s.overrides);
  validate_backend_knobs(s.scene);  // the same checks (and messages) as `chainmail check`
  return s;
}

void add_scene(py::module_& m) {
  py::class_<PyScene>(m, "Scene", "a validated scene (chainmail.load_scene)")
      .def_property_readonly("name", [](const PyScene& s) { return s.scene.name; })
      .def_property_readonly("path", [](const PyScene& s) { return s.path; })
      .def_property_readonly("overrides", [](const PyScene& s) { return s.overrides; })
      .def_property_readonly("duration", [](const PyScene& s) { return s.scene.duration; })
      .def(
          "to_dict", [](const PyScene& s) { return to_python(scene_to_json(s.scene)); },
          "the resolved scene, every default filled in (summary.json's \"scene\")")
      .def("__repr__", [](const PyScene& s) {
        return "<chainmail.Scene '" + s.scene.name + "' from " + s.path + ">";
      });
  m.def("load_scene", &load_scene, py::arg("path"), py::arg("overrides") = py::dict(),
        "read and validate a scene file; overrides {dotted.key: value} as `--set` applies them. "
        "Raises SceneError naming the file and key.");
}

}  // namespace
}  // namespace chainmail::python

PYBIND11_MODULE(_chainmail, m) {
  namespace cm = chainmail;
  namespace py = pybind11;
  m.doc() = "chainmail: interlocking-ring fabric through several physics models";
  py::register_exception<cm::SceneError>(m, "SceneError", PyExc_ValueError);
  py::register_exception<cm::UsageError>(m, "UsageError", PyExc_ValueError);
  py::register_exception<cm::OutputError>(m, "OutputError", PyExc_OSError);
  m.attr("__version__") = cm::chainmail_version();
  m.def(
      "backends", [] { return cm::python::to_python(cm::backends_json()["backends"]); },
      "every backend: name, built, summary and its knobs (type, default, min, max, help)");
  cm::python::add_scene(m);
  cm::python::add_simulation(m);
  cm::python::add_commands(m);
}
