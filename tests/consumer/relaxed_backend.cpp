#include "relaxed_backend.hpp"

#include <memory>

#include <chainmail/backends/backend.hpp>
#include <chainmail/core/plausible/plausible.hpp>

namespace consumer {
namespace {

using chainmail::PlausibleSettings;

// the model's settings with this backend's defaults (the knob table reads them from S{})
struct RelaxedSettings : PlausibleSettings {
  RelaxedSettings() { damping = 2.0; }
};

const chainmail::KnobTable<RelaxedSettings>& relaxed_knobs() {
  using S = RelaxedSettings;
  static const chainmail::KnobTable<S> table = [] {
    chainmail::KnobTable<S> t;
    t.time_step(0.004, 1e-5, 0.01, "time step, s");
    t.integer("iterations", &S::iterations, 1, 1000, "constraint sweeps per step");
    t.number("damping", &S::damping, 0.0, 100.0, "velocity drag, 1/s");
    return t;
  }();
  return table;
}

class RelaxedBackend final : public chainmail::Backend {
 public:
  const char* name() const override { return "relaxed"; }
  void reset(const chainmail::Scene& scene, const chainmail::Weave& weave,
             const chainmail::Knobs& knobs) override {
    sim_.reset(scene, weave, relaxed_knobs().settings(knobs));
  }
  chainmail::StepStatus step(double dt) override {
    sim_.step(dt);
    return chainmail::StepStatus::ok;
  }
  void frame(chainmail::RingFrame& out) const override { sim_.frame(out); }
  const chainmail::StageProfile& profile() const override { return sim_.profile(); }

 private:
  chainmail::PlausibleSim sim_;
};

}  // namespace

void register_relaxed_backend() {
  chainmail::BackendInfo info;
  info.name = "relaxed";
  info.summary = "the plausible model with light drag (registered from outside)";
  info.knobs = relaxed_knobs().specs();
  info.knob_round_trip = relaxed_knobs().round_trip();
  info.cost_us_per_ring_step = 1.0;
  info.bytes_per_ring = 1000;
  info.create = [] { return std::make_unique<RelaxedBackend>(); };
  chainmail::register_backend(info);
}

}  // namespace consumer
