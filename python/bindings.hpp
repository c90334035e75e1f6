// The Python module's pieces: a scene as Python holds it, and the functions each source file adds
// to the module. Everything they do goes through the harness (bench/harness/); nothing here
// measures, runs or writes on its own.
#pragma once

#include <string>
#include <vector>

#include <pybind11/pybind11.h>
#include <nlohmann/json.hpp>

#include "core/scene.hpp"

namespace chainmail::python {

namespace py = pybind11;

// a loaded scene and how it was loaded, so that commands that read the file again (run into a
// folder, sweep) see the very same scene
struct PyScene {
  std::string path;
  std::vector<std::string> overrides;  // dotted.key=value, as --set takes them
  Scene scene;
};

// a text argument (path, name) refused with ValueError naming it where it holds a NUL byte, which
// the file system would cut it at
void check_text(const std::string& argument, const std::string& value);
// threads as the command line's --threads takes them, 0 for the default (ValueError otherwise)
int checked_threads(int threads);

// load_scene's overrides: {key: value} -> "key=<value as JSON>"
std::vector<std::string> override_texts(const py::dict& overrides);
// a JSON document as Python objects (dict, list, float, ...)
py::object to_python(const nlohmann::json& value);

void add_simulation(py::module_& m);  // simulation.cpp: Simulation, render
void add_commands(py::module_& m);    // commands.cpp: run, sweep

}  // namespace chainmail::python
