// One backend's model that several threads may step and read: steps are serialised by a lock
// of the model's own, and a reader gets a copy of the frame taken between two steps, never one
// half written. The Python module's Simulation is this with arrays on top.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include "backends/backend.hpp"
#include "core/frame.hpp"
#include "core/scene.hpp"
#include "core/weave.hpp"

namespace chainmail {

class SharedModel {
 public:
  // `scene` loaded and validated; `backend` a built one (UsageError otherwise); threads 0: every
  // hardware thread
  SharedModel(Scene scene, const std::string& backend, int threads);

  // the checks a step's arguments get, as the command line's: dt finite, positive and within the
  // backend's dt knob range; n at least 1. Throw std::invalid_argument naming the argument.
  void check_step(double dt, long long n) const;
  // one step of dt under the lock; false once the model's state is not finite (it then stops)
  bool step(double dt);
  // the current frame, copied under the lock into `out` (whose memory is reused when the size
  // is the same, so views of it stay valid); returns the steps taken up to it
  long long read_frame(RingFrame& out) const;
  long long steps() const;

  const Scene& scene() const { return scene_; }
  const Weave& weave() const { return weave_; }
  const Knobs& knobs() const { return knobs_; }
  const std::string& backend() const { return backend_name_; }

 private:
  std::string backend_name_;
  Scene scene_;
  Weave weave_;
  Knobs knobs_;
  double dt_min_ = 0.0, dt_max_ = 0.0;  // s, the backend's dt knob range
  std::unique_ptr<Backend> model_;
  mutable std::mutex lock_;  // held for a step and for a copy of the frame
  long long steps_ = 0;
  bool finite_ = true;
};

}  // namespace chainmail
