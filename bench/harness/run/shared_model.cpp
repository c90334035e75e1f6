// SharedModel: a backend stepped and read from several threads in turn.
#include "bench/harness/run/shared_model.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "backends/open_backend.hpp"
#include "bench/harness/common/usage_error.hpp"
#include "bench/harness/run/run.hpp"
#include "core/parallel.hpp"

namespace chainmail {

SharedModel::SharedModel(Scene scene, const std::string& backend, int threads)
    : backend_name_(backend), scene_(std::move(scene)) {
  if (threads < 0 || threads > 4096) {
    throw std::invalid_argument("threads: " + std::to_string(threads) + " is outside 0 to 4096");
  }
  // unknown or unbuilt: UsageError naming it; "all" (which a run takes) names no one backend
  const std::vector<std::string> chosen = select_backends(scene_, {backend});
  const BackendInfo* found = find_backend(backend);
  if (chosen.size() != 1 || !found) {
    throw UsageError("backend '" + backend + "': one backend is needed (" +
                     join_names(built_backend_names()) + ")");
  }
  const KnobSpec* dt = find_knob(*found, "dt");
  dt_min_ = dt->min, dt_max_ = dt->max;
  weave_ = make_weave(scene_.weave, scene_.ring);
  OpenedBackend opened =
      open_backend(scene_, weave_, *found, threads > 0 ? threads : hardware_threads());
  model_ = std::move(opened.model);
  knobs_ = std::move(opened.knobs);
}

void SharedModel::check_step(double dt, long long n) const {
  if (n < 1) throw std::invalid_argument("n: " + std::to_string(n) + " steps, at least 1 needed");
  if (!std::isfinite(dt) || dt < dt_min_ || dt > dt_max_) {
    std::ostringstream text;
    text << "dt: " << dt << " s is outside the " << backend_name_ << " dt range [" << dt_min_
         << ", " << dt_max_ << "]";
    throw std::invalid_argument(text.str());
  }
}

bool SharedModel::step(double dt) {
  const std::lock_guard<std::mutex> hold(lock_);
  if (!finite_) return false;
  finite_ = model_->step(dt) == StepStatus::ok;
  ++steps_;
  return finite_;
}

long long SharedModel::read_frame(RingFrame& out) const {
  const std::lock_guard<std::mutex> hold(lock_);
  model_->frame(out);
  return steps_;
}

long long SharedModel::steps() const {
  const std::lock_guard<std::mutex> hold(lock_);
  return steps_;
}

}  // namespace chainmail
