// Adapter: rings as rigid tori with exact torus-torus contact in XPBD
// (core/torus_xpbd/torus_xpbd.hpp) behind the Backend interface.
#include "backends/backend.hpp"
#include "core/parallel.hpp"
#include "core/torus_xpbd/torus_xpbd.hpp"

namespace chainmail {
namespace {

// every knob once, bound to its TorusXpbdSettings field (the field's default is the knob's)
const KnobTable<TorusXpbdSettings>& torus_xpbd_knobs() {
  using S = TorusXpbdSettings;
  static const KnobTable<S> table = [] {
    KnobTable<S> t;
    t.time_step(0.005, 1e-6, 0.1, "time step, s")
        .unit("s")
        .doc("time step (a tenth of the default sample interval)");
    t.integer("substeps", &S::substeps, 1, 10000, "substeps per step, one constraint pass each")
        .doc("substeps per step, one constraint pass each (more when rings fly fast, see below)");
    t.number("friction", &S::friction, 0.0, 10.0,
             "factor on the scene's Coulomb coefficients (0: frictionless)")
        .doc(
            "factor on the scene's Coulomb coefficients (`ring.friction`, each collider's "
            "`friction`); 0: frictionless");
    t.number("restitution", &S::restitution, 0.0, 1.0, "normal restitution of every contact");
    t.number("compliance", &S::compliance, 0.0, 1e3, "contact compliance, m/N (0: rigid)")
        .unit("m/N")
        .doc("contact compliance (0: rigid)");
    t.number("damping", &S::damping, 0.0, 1e4, "linear and angular velocity drag, 1/s")
        .unit("1/s")
        .doc(
            "linear and angular velocity drag: velocities are multiplied by exp(−damping · h) "
            "every substep h");
    t.integer("velocity_iterations", &S::velocity_iterations, 1, 1000,
              "Gauss-Seidel passes of the velocity solve (restitution, dynamic friction) per "
              "substep, the first two over every contact, the others over those near colliders")
        .doc(
            "Gauss-Seidel passes of the velocity solve (restitution, dynamic friction) per "
            "substep, the first two over every contact, the others over those near colliders; "
            "friction's impulse over all of them at most `friction` times the normal one");
    t.boolean("sleeping", &S::sleeping,
              "rings at rest are not integrated until a contact moves them")
        .doc(
            "rings whose points all move slower than 1 mm/s for 0.3 s are no longer integrated "
            "until a contact moves them");
    t.choice("friction_law", &S::friction_law, {"cone", "pyramid"},
             "cone: Coulomb's bound in every direction; pyramid: the bound on each of two "
             "tangent axes, as Bullet and ODE solve it")
        .doc(
            "`cone`: Coulomb's cone, `friction` times the normal force in every tangent "
            "direction. `pyramid`: that bound on each of two fixed tangent axes of each contact, "
            "as Bullet's two friction directions and ODE's `dContactApprox1` solve it, which "
            "holds up to √2 times more on the diagonals");
    return t;
  }();
  return table;
}

class TorusXpbdBackend final : public Backend {
 public:
  const char* name() const override { return "torus_xpbd"; }
  void set_threads(int threads) override { threads_ = threads; }
  void reset(const Scene& scene, const Weave& weave, const Knobs& knobs) override {
    sim_.reset(scene, weave, torus_xpbd_knobs().settings(knobs));
  }
  StepStatus step(double dt) override {
    // a team waits for a core at each of a substep's barriers: no more threads than are free
    sim_.set_threads(threads_for_step(threads_));
    sim_.step(dt);
    return sim_.finite() ? StepStatus::ok : StepStatus::non_finite;
  }
  void frame(RingFrame& out) const override { sim_.frame(out); }
  const StageProfile& profile() const override { return sim_.profile(); }

 private:
  TorusXpbdSim sim_;
  int threads_ = 1;  // asked for; each step uses those the machine leaves free
};

}  // namespace

BackendInfo torus_xpbd_backend_info() {
  BackendInfo info;
  info.name = "torus_xpbd";
  info.cost_us_per_ring_step = 100;  // 16 x 16 curtain: 68 on one thread, 41 on two; 64 x 64: 165
  info.multithreaded = true;
  info.bytes_per_ring = 3000;
  info.summary = "rigid tori with exact torus-torus contact, extended position-based dynamics";
  info.knobs = torus_xpbd_knobs().specs();
  info.knob_round_trip = torus_xpbd_knobs().round_trip();
  info.create = [] { return std::make_unique<TorusXpbdBackend>(); };
  return info;
}

}  // namespace chainmail
