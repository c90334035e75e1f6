// chainmail.Simulation: one backend stepped from Python, its frame as NumPy arrays that share the
// frame's memory; chainmail.render: simulations drawn side by side into an (H, W, 3) array.
#include <algorithm>
#include <cstdio>
#include <memory>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "backends/backend.hpp"
#include "bench/harness/common/data_dir.hpp"
#include "bench/harness/output/output.hpp"
#include "bench/harness/run/run.hpp"
#include "bench/harness/run/shared_model.hpp"
#include "core/metrics.hpp"
#include "python/bindings.hpp"
#include "scene_file/scene_file.hpp"
#if CHAINMAIL_HAVE_RENDER
#include "core/parallel.hpp"
#include "render/renderer.hpp"
#endif

namespace chainmail::python {
namespace {

// a step's or a path's argument refused as the command line refuses it: ValueError naming it
[[noreturn]] void refuse(const std::string& what) {
  throw py::value_error(what);
}

class Simulation {
 public:
  Simulation(const PyScene& scene, const std::string& backend, const py::dict& knobs, int threads)
      : shared_(load(scene, backend, knobs), backend, checked_threads(threads)) {
    shared_.read_frame(frame_);
  }

  // n steps of dt (the backend's dt knob when None). Each step releases the GIL and takes the
  // simulation's lock, so steps from several threads are serialised; a signal (Ctrl-C) is looked
  // at between steps. False once the model's state is not finite.
  bool step(std::optional<double> dt, long long n) {
    const double h = dt.value_or(shared_.knobs().at("dt"));
    try {
      shared_.check_step(h, n);
    } catch (const std::invalid_argument& e) {
      refuse(std::string("step: ") + e.what());
    }
    bool ok = true;
    for (long long k = 0; k < n && ok; ++k) {
      {
        py::gil_scoped_release release;
        ok = shared_.step(h);
      }
      if (PyErr_CheckSignals() != 0) {
        refresh();  // where it got to, for the handler
        throw py::error_already_set();
      }
    }
    refresh();
    return ok;
  }

  // summary.json's "final" for the current frame (drape_rms absent: no reference here)
  py::object metrics() const {
    return to_python(metrics_json(measure(frame_, shared_.weave(), shared_.scene())));
  }

  // copies of the current frame's arrays, taken under the lock: a state between two steps even
  // while another thread steps (the views are refreshed at the end of a step() call only)
  py::dict snapshot() const {
    RingFrame copy;
    {
      py::gil_scoped_release release;
      shared_.read_frame(copy);
    }
    auto rows = [](const auto& m) {
      py::array_t<double> a(
          {static_cast<py::ssize_t>(m.cols()), static_cast<py::ssize_t>(m.rows())});
      std::copy(m.data(), m.data() + m.size(), a.mutable_data());
      return a;
    };
    py::dict out;
    out["t"] = copy.t;
    out["positions"] = rows(copy.position);
    out["orientations"] = rows(copy.orientation);
    out["velocities"] = rows(copy.velocity);
    return out;
  }

  std::string hash() const {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx",
                  static_cast<unsigned long long>(frame_hash(frame_)));
    return text;
  }

  const Scene& scene() const { return shared_.scene(); }
  const Weave& weave() const { return shared_.weave(); }
  const RingFrame& frame() const { return frame_; }
  const std::string& backend() const { return shared_.backend(); }
  const Knobs& knobs() const { return shared_.knobs(); }
  long long steps() const {
    py::gil_scoped_release release;  // the lock is never waited for with the GIL held
    return shared_.steps();
  }

 private:
  static Scene load(const PyScene& scene, const std::string& backend, const py::dict& knobs) {
    check_text("backend", backend);
    // the knobs as overrides of backends.<name>, so that they are checked as a scene file's are
    std::vector<std::string> sets = scene.overrides;
    for (const std::string& knob : override_texts(knobs))
      sets.push_back("backends." + backend + "." + knob);
    Scene loaded = load_scene_file(scene.path, sets);
    validate_backend_knobs(loaded);
    return loaded;
  }

  // the views' frame from the model: copied with the GIL released (waiting for the lock while a
  // step runs), then into frame_ with the GIL held, so that Python never reads it half written;
  // the same size, so frame_'s memory (which the views show) stays where it is. Of two threads
  // refreshing at once, the copy of the later state wins, whichever gets the GIL first.
  void refresh() {
    RingFrame copy;
    long long steps = 0;
    {
      py::gil_scoped_release release;
      steps = shared_.read_frame(copy);
    }
    if (steps < frame_steps_) return;
    frame_ = copy;
    frame_steps_ = steps;
  }

  SharedModel shared_;
  RingFrame frame_;  // refreshed at the end of every step() call; the arrays below view it
  long long frame_steps_ = 0;  // the steps taken up to frame_
};

// the resolved knobs, a choice as its name (as a scene gives it)
py::dict knobs_dict(const Simulation& sim) {
  py::dict out;
  const BackendInfo* info = find_backend(sim.backend());
  for (const auto& [name, value] : sim.knobs()) {
    const KnobSpec* spec = info ? find_knob(*info, name) : nullptr;
    if (spec && spec->type == KnobSpec::Type::choice)
      out[py::str(name)] = choice_name(*spec, value);
    else
      out[py::str(name)] = value;
  }
  return out;
}

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
void check_render_arguments(size_t count, int width, int height, const std::string& material,
                            int samples) {
  if (count == 0) refuse("simulations: no simulation to draw");
  // as `chainmail render --size WxH --samples N --material NAME` take them
  if (width < 16 || width > 8192)
    refuse("width: " + std::to_string(width) + " pixels, expected 16 to 8192");
  if (height < 16 || height > 8192)
    refuse("height: " + std::to_string(height) + " pixels, expected 16 to 8192");
  if (samples < 0 || samples > 16)
    refuse("samples: " + std::to_string(samples) + ", expected 0 to 16");
  const std::vector<std::string> names = render::material_names();
  if (std::find(names.begin(), names.end(), material) == names.end()) {
    std::string known;
    for (const std::string& name : names) known += (known.empty() ? "" : ", ") + name;
    refuse("material: unknown '" + material + "' (" + known + ")");
  }
}

py::array_t<std::uint8_t> render_frames(const std::vector<const Simulation*>& sims, int width,
                                        int height, const std::string& material, int samples) {
  check_render_arguments(sims.size(), width, height, material, samples);
  render::RenderSettings settings;
  settings.shader_dir = render_shader_dir();
  settings.width = width, settings.height = height, settings.samples = samples;
  settings.material = material;
  settings.cloth_shader = "texture";  // as `chainmail run --render` draws the cloth baseline
  // the frames copied with the GIL held (when a step() call refreshes them), drawn without it
  std::vector<RingFrame> frames;
  for (const Simulation* s : sims) frames.push_back(s->frame());
  std::vector<render::Panel> panels;
  for (size_t k = 0; k < sims.size(); ++k) {
    const BackendInfo* info = find_backend(sims[k]->backend());
    panels.push_back({sims[k]->backend(), &frames[k], info && info->cloth_surface});
  }
  render::Image image;
  {
    py::gil_scoped_release release;
    try {
      image =
          render::Renderer::create(settings)->render(sims[0]->scene(), sims[0]->weave(), panels);
    } catch (const render::RenderError& e) {
      // the renderer's messages already begin with "render: "
      const std::string what = e.what();
      throw SceneError(what.rfind("render: ", 0) == 0 ? what : "render: " + what);
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
      .def("snapshot", &Simulation::snapshot,
           "{t, positions, orientations, velocities}: copies taken between two steps, even while "
           "another thread steps")
      .def("metrics", &Simulation::metrics, "the metrics of the current frame, as summary.json")
      .def_property_readonly("t", [](const Simulation& s) { return s.frame().t; })
      .def_property_readonly("steps", &Simulation::steps)
      .def_property_readonly("hash", &Simulation::hash, "frame_hash of the current frame (hex)")
      .def_property_readonly("backend", &Simulation::backend)
      .def_property_readonly("knobs", &knobs_dict)
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
