// chainmail.Simulation: one backend stepped from Python, its frame as NumPy arrays that share the
// frame's memory; chainmail.render: simulations drawn side by side into an (H, W, 3) array.
#include <cstdio>
#include <memory>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "backends/backend.hpp"
#include "bench/harness/data_dir.hpp"
#include "bench/harness/output.hpp"
#include "bench/harness/run.hpp"
#include "bench/harness/scene_file.hpp"
#include "core/metrics.hpp"
#include "python/bindings.hpp"
#if CHAINMAIL_HAVE_RENDER
#include "core/parallel.hpp"
#include "render/renderer.hpp"
#endif

namespace chainmail::python {
namespace {

class Simulation {
 public:
  Simulation(const PyScene& scene, const std::string& backend, const py::dict& knobs, int threads)
      : backend_name_(backend) {
    if (threads < 0) throw py::value_error("threads: " + std::to_string(threads) + " is below 0");
    // the knobs as overrides of backends.<name>, so that they are checked as a scene file's are
    std::vector<std::string> sets = scene.overrides;
    for (const std::string& knob : override_texts(knobs))
      sets.push_back("backends." + backend + "." + knob);
    scene_ = load_scene_file(scene.path, sets);
    validate_backend_knobs(scene_);
    select_backends(scene_, {backend});  // unknown or unbuilt: UsageError naming it
    const BackendInfo& info = *find_backend(backend);
    knobs_ = resolve_knobs(scene_, info);
    weave_ = make_weave(scene_.weave, scene_.ring);
    model_ = info.create();
    model_->set_threads(threads > 0 ? threads : hardware_threads());
    model_->reset(scene_, weave_, knobs_);
    model_->frame(frame_);
  }

  // n steps of dt (the backend's dt knob when None); the GIL is released while a step runs and
  // a signal (Ctrl-C) is looked at between steps. False once the model's state is not finite.
  bool step(std::optional<double> dt, long long n) {
    const double h = dt.value_or(knobs_.at("dt"));
    if (!(h > 0.0)) throw py::value_error("step: dt must be positive");
    bool ok = finite_;
    for (long long k = 0; k < n && ok; ++k) {
      {
        py::gil_scoped_release release;
        ok = model_->step(h) == StepStatus::ok;
      }
      ++steps_;
      if (PyErr_CheckSignals() != 0) {
        model_->frame(frame_);  // where it got to, for the handler
        throw py::error_already_set();
      }
    }
    finite_ = ok;
    model_->frame(frame_);
    return ok;
  }

  // summary.json's "final" for the current frame (drape_rms absent: no reference here)
  py::object metrics() const { return to_python(metrics_json(measure(frame_, weave_, scene_))); }

  std::string hash() const {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx",
                  static_cast<unsigned long long>(frame_hash(frame_)));
    return text;
  }

  const Scene& scene() const { return scene_; }
  const Weave& weave() const { return weave_; }
  const RingFrame& frame() const { return frame_; }
  const std::string& backend() const { return backend_name_; }
  const Knobs& knobs() const { return knobs_; }
  long long steps() const { return steps_; }

 private:
  std::string backend_name_;
  Scene scene_;
  Weave weave_;
  Knobs knobs_;
  std::unique_ptr<Backend> model_;
  RingFrame frame_;  // refreshed after every step() call; the arrays below view it
  long long steps_ = 0;
  bool finite_ = true;
};

// a read-only (rows, cols) view of a column-major (cols, rows) Eigen matrix: its columns are the
// view's rows, so no copy is needed; `owner` keeps the memory alive
template <class Matrix>
py::array_t<double> rows_view(const Matrix& m, py::handle owner) {
  const auto cols = static_cast<py::ssize_t>(m.rows());
  py::array_t<double> view(
      {static_cast<py::ssize_t>(m.cols()), cols},
      {static_cast<py::ssize_t>(sizeof(double)) * cols, static_cast<py::ssize_t>(sizeof(double))},
      m.data(), owner);
  view.attr("setflags")(py::arg("write") = false);
  return view;
}

#if CHAINMAIL_HAVE_RENDER
// the simulations' current frames side by side, one panel each, as (height, width * n, 3) uint8
py::array_t<std::uint8_t> render_frames(const std::vector<const Simulation*>& sims, int width,
                                        int height, const std::string& material, int samples) {
  if (sims.empty()) throw py::value_error("render: no simulation to draw");
  render::RenderSettings settings;
  settings.shader_dir = render_shader_dir();
  settings.width = width, settings.height = height, settings.samples = samples;
  settings.material = material;
  settings.cloth_shader = "texture";  // as `chainmail run --render` draws the cloth baseline
  std::vector<render::Panel> panels;
  for (const Simulation* s : sims) {
    const BackendInfo* info = find_backend(s->backend());
    panels.push_back({s->backend(), &s->frame(), info && info->cloth_surface});
  }
  render::Image image;
  {
    py::gil_scoped_release release;
    try {
      image =
          render::Renderer::create(settings)->render(sims[0]->scene(), sims[0]->weave(), panels);
    } catch (const render::RenderError& e) {
      throw SceneError(std::string("render: ") + e.what());
    }
  }
  py::array_t<std::uint8_t> rgb({image.height, image.width, 3});
  auto out = rgb.mutable_unchecked<3>();
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < 3; ++c) out(y, x, c) = image.rgba[4 * (y * image.width + x) + c];
  return rgb;
}
#endif

}  // namespace

void add_simulation(py::module_& m) {
  py::class_<Simulation>(m, "Simulation", "one backend stepped from Python")
      .def(py::init<const PyScene&, const std::string&, const py::dict&, int>(), py::arg("scene"),
           py::arg("backend"), py::arg("knobs") = py::dict(), py::arg("threads") = 0,
           "threads: those step() may use (0: every hardware thread)")
      .def("step", &Simulation::step, py::arg("dt") = py::none(), py::arg("n") = 1,
           "advance n steps of dt (default: the backend's dt knob); False once not finite")
      .def("metrics", &Simulation::metrics, "the metrics of the current frame, as summary.json")
      .def_property_readonly("t", [](const Simulation& s) { return s.frame().t; })
      .def_property_readonly("steps", &Simulation::steps)
      .def_property_readonly("hash", &Simulation::hash, "frame_hash of the current frame (hex)")
      .def_property_readonly("backend", &Simulation::backend)
      .def_property_readonly("knobs", &Simulation::knobs)
      .def_property_readonly("dt", [](const Simulation& s) { return s.knobs().at("dt"); })
      .def_property_readonly("rings", [](const Simulation& s) { return s.frame().size(); })
      .def_property_readonly(
          "positions",
          [](py::object self) {
            return rows_view(self.cast<const Simulation&>().frame().position, self);
          },
          "(N, 3) ring centres, m: a read-only view, updated by step()")
      .def_property_readonly(
          "orientations",
          [](py::object self) {
            return rows_view(self.cast<const Simulation&>().frame().orientation, self);
          },
          "(N, 4) unit quaternions (w, x, y, z): a read-only view, updated by step()")
      .def_property_readonly(
          "velocities",
          [](py::object self) {
            return rows_view(self.cast<const Simulation&>().frame().velocity, self);
          },
          "(N, 3) ring velocities, m/s: a read-only view, updated by step()");
#if CHAINMAIL_HAVE_RENDER
  m.def(
      "render",
      [](const std::vector<const Simulation*>& sims, int width, int height,
         const std::string& material,
         int samples) { return render_frames(sims, width, height, material, samples); },
      py::arg("simulations"), py::arg("width") = 640, py::arg("height") = 360,
      py::arg("material") = "steel", py::arg("samples") = 4,
      "the simulations' current frames side by side through the renderer: (H, W * n, 3) uint8");
#endif
}

}  // namespace chainmail::python
