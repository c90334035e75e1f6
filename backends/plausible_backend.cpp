// Adapter: the paper's plausible model (core/plausible/plausible.hpp) behind the Backend interface.
#include <numbers>
#include <string>

#include "backends/backend.hpp"
#include "core/parallel.hpp"
#include "core/plausible/plausible.hpp"

namespace chainmail {
namespace {

using PlausibleKnobs = KnobTable<PlausibleSettings>;

// the step, the sweeps and the links
void add_step_knobs(PlausibleKnobs& t) {
  using S = PlausibleSettings;
  t.time_step(0.004, 1e-6, 0.1, "time step, s").unit("s").doc("time step");
  t.integer("iterations", &S::iterations, 1, 100000, "most constraint sweeps per step");
  t.number("tolerance", &S::tolerance, 0.0, 1.0,
           "sweeps stop once the largest violation met is below this fraction of the link length")
      .doc(
          "the sweeps, and the Newton steps after them, stop once the largest violation is "
          "below this fraction of the link length");
  t.integer("newton_steps", &S::newton_steps, 0, 10000,
            "most Newton steps on edges and colliders together after the sweeps (0: sweeps only)");
  t.boolean("link_geometry", &S::link_geometry,
            "largest neighbour distance from the ring geometry, by the rings' orientation")
      .doc("largest neighbour distance from the ring geometry (see below)");
  t.number("max_link_fraction", &S::max_link_fraction, 0.2, 1.0,
           "largest neighbour distance / inner diameter (without link_geometry, or where the "
           "geometry gives none)")
      .doc(
          "largest neighbour distance / inner diameter, without `link_geometry` or where the "
          "geometry gives none");
  t.number("damping", &S::damping, 0.0, 1000.0,
           "damping of motion other than rigid motion of the whole, 1/s")
      .unit("1/s")
      .doc(
          "each step pulls velocities a fraction min(1, damping · dt) toward the rigid motion "
          "that fits the free rings best");
  t.boolean("damp_rigid", &S::damp_rigid,
            "damping slows all motion, rigid motion included (a drag)")
      .doc("damping pulls toward rest instead: a drag on all motion, rigid motion included");
}

// the non-neighbours and the colliders
void add_contact_knobs(PlausibleKnobs& t) {
  using S = PlausibleSettings;
  t.number("repulsion_fraction", &S::repulsion_fraction, 0.0, 2.0,
           "non-neighbour minimum distance (or repulsion spring range) / inner diameter")
      .doc(
          "minimum distance between non-neighbour rings (or range of the repulsion spring) / "
          "inner diameter");
  t.boolean("repulsion_spring", &S::repulsion_spring,
            "non-neighbours repel by the paper's spring (explicit) instead of a minimum distance")
      .doc(
          "non-neighbours repel by the paper's spring k (r − d), integrated explicitly, "
          "instead of a minimum distance");
  t.number("repulsion_stiffness", &S::repulsion_stiffness, 0.0, 1e9,
           "stiffness of the repulsion spring, N/m")
      .unit("N/m")
      .doc("stiffness of that spring");
  t.number("contact_skin", &S::contact_skin, 0.0, 10.0,
           "repulsion candidate list margin, fraction of the range (0 = rebuild every step)")
      .doc(
          "margin of the non-neighbour candidate list, as a fraction of the range (0: rebuild "
          "every step)");
  t.number("contact_margin", &S::contact_margin, 0.0, 1.0,
           "distance kept between a ring centre and a collider, m (0: the torus's extent along "
           "the collider normal from the ring's orientation)")
      .unit("m")
      .doc(
          "distance kept between a ring centre and a collider (0: the torus's own extent along "
          "the collider normal)");
}

// the pins and the substeps
void add_pin_knobs(PlausibleKnobs& t) {
  using S = PlausibleSettings;
  t.boolean("swivel", &S::swivel, "swivel rings into the 4-in-1 pattern");
  t.boolean("shock_propagation", &S::shock_propagation,
            "a constraint pass outward from the pins before the sweeps, moving only the far ring")
      .doc(
          "a constraint pass outward from the pins, before the sweeps, that moves only the "
          "ring farther from a pin");
  t.boolean("pin_attachments", &S::pin_attachments,
            "long-range attachments: no ring farther from its nearest pins than its links "
            "allow (keeps large hanging sheets from stretching)")
      .doc(
          "long-range attachments: no ring farther from its nearest pins than its links to "
          "them allow (below)");
  // the automatic range is the model's own (PlausibleSim::kMinSubsteps to kMaxSubsteps)
  const std::string automatic = "(0: automatic, " + std::to_string(PlausibleSim::kMinSubsteps) +
                                " to " + std::to_string(PlausibleSim::kMaxSubsteps) +
                                " from the stretch the sweeps leave and the rings' speed";
  t.integer("substeps", &S::substeps, 0, 10000,
            "equal substeps per step, the step's sweeps shared among them " + automatic + ")")
      .doc("equal substeps per step, the step's sweeps shared among them " + automatic +
           ", below)");
  t.number("newton_level", &S::newton_level, 0.0, 1000.0,
           "Newton steps run where the sweeps leave a violation past this fraction of the way "
           "from the longest link to the inner diameter (0: wherever they leave more than the "
           "tolerance)");
}

// the rings' orientation and the compression limits
void add_shape_knobs(PlausibleKnobs& t) {
  using S = PlausibleSettings;
  t.number("swivel_extended", &S::swivel_extended, 0.0, 0.5 * std::numbers::pi,
           "swivel angle at full extension, rad (0: the paper's a/c)")
      .unit("rad")
      .doc("swivel angle at full extension, with `swivel_fit` off (0: the paper's a/c)");
  t.boolean("swivel_fit", &S::swivel_fit,
            "swivel at full extension fitted to the ring geometry (most neighbour clearance)")
      .doc(
          "take the swivel at full extension from the ring geometry (most clearance between "
          "neighbours; 26° at AR 5) instead of `swivel_extended`");
  t.boolean("compression_limits", &S::compression_limits,
            "4-in-1: neighbours, rings sharing two neighbours and rings a row and a half apart "
            "come no closer than the ring geometry lets them (off: the paper's wire thickness "
            "between neighbours only)")
      .doc(
          "4-in-1: neighbours, rings that share two neighbours and rings a row and a half "
          "apart come no closer (rings of one row: and no farther apart) than the ring "
          "geometry lets them (see below); off: the paper's rule, neighbours as close as the "
          "wire thickness and nothing else");
  t.number("row_slip", &S::row_slip, 0.0, 1.0,
           "4-in-1: rings side by side in a row pushed together slide out of the sheet toward "
           "the faces they lean to, by this fraction of their axes across the push (0: straight "
           "apart)")
      .doc(
          "4-in-1 with `compression_limits`: rings side by side in a row, pushed together to their "
          "closest approach, are pushed apart along a way turned toward their axes by this "
          "fraction, so they slide out of the sheet like leaning coins (see below); 0: along the "
          "line between their centres (the default: see below for what it costs)");
  t.boolean("swivel_from_pins", &S::swivel_from_pins,
            "4-in-1: each ring swivels about the direction toward the pins it hangs from, "
            "propagated through the weave (off: one pattern for the whole sheet)")
      .doc(
          "4-in-1: each ring swivels about a hinge turned toward the pins it hangs from, "
          "propagated through the weave (paper §6); off: one pattern for the whole sheet");
}

// every knob once, bound to its PlausibleSettings field (the field's default is the knob's), in
// the order `chainmail backends` and docs/backends.md list them
const PlausibleKnobs& plausible_knobs() {
  static const PlausibleKnobs table = [] {
    PlausibleKnobs t;
    add_step_knobs(t);
    add_contact_knobs(t);
    add_pin_knobs(t);
    add_shape_knobs(t);
    return t;
  }();
  return table;
}

class PlausibleBackend final : public Backend {
 public:
  const char* name() const override { return "plausible"; }
  void reset(const Scene& scene, const Weave& weave, const Knobs& knobs) override {
    sim_.reset(scene, weave, plausible_knobs().settings(knobs));
  }
  StepStatus step(double dt) override {
    sim_.set_threads(threads_for_step(threads_));
    sim_.step(dt);
    return StepStatus::ok;
  }
  void frame(RingFrame& out) const override { sim_.frame(out); }
  const StageProfile& profile() const override { return sim_.profile(); }
  void set_threads(int threads) override {
    threads_ = threads;
    sim_.set_threads(threads);
  }

 private:
  PlausibleSim sim_;
  int threads_ = 1;  // asked for; each step uses those the machine leaves free
};

}  // namespace

BackendInfo plausible_backend_info() {
  BackendInfo info;
  info.name = "plausible";
  info.cost_us_per_ring_step = 12.0;
  info.multithreaded = true;
  info.bytes_per_ring = 1000;
  info.summary = "the paper's mass-per-ring model: Provot edge constraints, repulsion, swivel";
  info.knobs = plausible_knobs().specs();
  info.knob_round_trip = plausible_knobs().round_trip();
  info.create = [] { return std::make_unique<PlausibleBackend>(); };
  return info;
}

}  // namespace chainmail
