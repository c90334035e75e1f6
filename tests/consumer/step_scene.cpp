// An installed scene stepped through the registry in the outside backend and in the built-in one
// it is made from: the catenary chain, pinned at both ends, at the knobs the scene gives
// plausible, which are the outside backend's defaults. Both must end in the same frame, bit for
// bit, and the chain must hang like a catenary.
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>

#include <chainmail/backends/backend.hpp>
#include <chainmail/core/weave.hpp>
#include <chainmail/scene_file/scene_file.hpp>

#include "relaxed_backend.hpp"

namespace {

// the final frame of `backend` after the scene's duration
chainmail::RingFrame final_frame(const chainmail::Scene& scene, const chainmail::Weave& weave,
                                 const std::string& backend) {
  const chainmail::BackendInfo* info = chainmail::find_backend(backend);
  const chainmail::Knobs knobs = chainmail::resolve_knobs(scene, *info);
  const double dt = knobs.at("dt");
  auto model = info->create();
  model->reset(scene, weave, knobs);
  const long long steps = std::llround(scene.duration / dt);
  for (long long k = 0; k < steps; ++k) model->step(dt);
  chainmail::RingFrame frame;
  model->frame(frame);
  std::printf("%-10s %lld steps of %g s, final frame %016llx\n", backend.c_str(), steps, dt,
              static_cast<unsigned long long>(chainmail::frame_hash(frame)));
  return frame;
}

// sag of an inextensible chain of length `length` between two points `span` apart at equal
// height: A from length = 2 A sinh(span / 2A) by bisection, sag = A (cosh(span / 2A) - 1)
double catenary_sag(double length, double span) {
  double low = 1e-6 * span, high = 1e6 * span;
  for (int k = 0; k < 200; ++k) {
    const double a = std::sqrt(low * high);
    (2.0 * a * std::sinh(span / (2.0 * a)) > length ? low : high) = a;
  }
  const double a = std::sqrt(low * high);
  return a * (std::cosh(span / (2.0 * a)) - 1.0);
}

}  // namespace

int main() {
  try {
    consumer::register_relaxed_backend();
    const chainmail::Scene scene =
        chainmail::load_scene_file(std::string(CHAINMAIL_SCENES) + "/chain_catenary.json");
    chainmail::validate_backend_knobs(scene);
    const chainmail::Weave weave = chainmail::make_weave(scene.weave, scene.ring);
    const chainmail::RingFrame relaxed = final_frame(scene, weave, "relaxed");
    const chainmail::RingFrame plausible = final_frame(scene, weave, "plausible");

    const int n = relaxed.size();
    const double span = (relaxed.position.col(n - 1) - relaxed.position.col(0)).norm();
    const double expected = catenary_sag((n - 1) * scene.ring.inner_diameter(), span);
    double sag = 0.0;  // m, lowest ring below the pins (gravity is -y)
    for (int ring = 0; ring < n; ++ring)
      sag = std::fmax(sag, relaxed.position(1, 0) - relaxed.position(1, ring));
    std::printf("sag %.2f mm, catenary %.2f mm\n", 1e3 * sag, 1e3 * expected);

    bool ok = true;
    if (chainmail::frame_hash(relaxed) != chainmail::frame_hash(plausible)) {
      std::printf("the outside backend and plausible end in different frames\n");
      ok = false;
    }
    // the plausible model's links stop at 0.95 ID and it leans on its constraints: about 10 %
    if (!(std::fabs(sag - expected) < 0.15 * expected)) {
      std::printf("the sag is more than 15 %% off the catenary\n");
      ok = false;
    }
    return ok ? 0 : 1;
  } catch (const std::exception& error) {
    std::printf("consumer: %s\n", error.what());
    return 1;
  }
}
