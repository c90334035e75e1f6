// The cloth document's mass-spring model as a chainmail backend: one point mass per ring, and ring
// orientations that follow the cloth surface with no swivel (the "cloth + texture" baseline).
#include <cmath>

#include "backends/backend.hpp"
#include "core/massspring/massspring_sim.hpp"

namespace chainmail {
namespace {

// the model's settings plus the adapter's own: the struct the knob table binds
struct MassSpringKnobs : massspring::Settings {
  int substeps = 0;  // Verlet steps per dt; 0 = the fewest that keep the springs stable
};

// every knob once, bound to its field (the field's default is the knob's); thickness 0 and the
// scene-derived fields are filled in by settings_from
const KnobTable<MassSpringKnobs>& massspring_knobs() {
  using S = massspring::Settings;
  static const KnobTable<MassSpringKnobs> table = [] {
    KnobTable<MassSpringKnobs> t;
    t.time_step(1.0 / 2700.0, 1e-7, 0.1, "time step, s (90 frames/s x 30 steps)")
        .unit("s")
        .doc("time step (90 frames/s × 30 steps)");
    t.integer("substeps", &MassSpringKnobs::substeps, 0, 1000,
              "Verlet steps per dt (0 = the fewest that keep the springs stable)")
        .doc("Verlet steps per `dt` (0: the fewest that keep the springs stable, below)");
    t.number("ks", &S::ks, 0.0, 1e9,
             "structural spring constant, N/m (0 = derived: the sheet stretches `stretch` under "
             "its own weight)")
        .unit("N/m")
        .doc("structural spring constant (0: derived from the sheet, below)");
    t.number("shear_ks", &S::shear_ks, 0.0, 1e9, "shear spring constant, N/m (0 = 0.02 ks)")
        .unit("N/m")
        .doc("shear spring constant (0: 0.02 `ks`)");
    t.number("bend_ks", &S::bend_ks, 0.0, 1e9, "bending spring constant, N/m (0 = 0.02 ks)")
        .unit("N/m")
        .doc("bending spring constant (0: 0.02 `ks`)");
    t.number("stretch", &S::stretch, 1e-6, 10.0,
             "the derived ks: stretch of a column as long as the sheet under its own weight, "
             "fraction of its length")
        .doc(
            "the derived `ks`: how far a column as long as the sheet stretches under its own "
            "weight, fraction of its length");
    t.number("damping_percent", &S::damping_percent, 0.0, 100.0,
             "Verlet damping, percent per 1/2700 s (the document's step) of motion other than "
             "rigid")
        .unit("%")
        .doc(
            "Verlet damping per document step (1/2700 s) of motion other than rigid motion (the "
            "document's: 0.2)");
    t.boolean("damp_rigid", &S::damp_rigid,
              "damping slows all motion, rigid motion included (the document's drag)")
        .doc("the damping slows all motion, rigid motion included (the document's drag)");
    t.integer("correction_passes", &S::correction_passes, 0, 10000,
              "over-extension correction passes per step (0 = off)")
        .doc("over-extension correction passes per step (0: off)");
    t.number("max_extension", &S::max_extension, 0.0, 10.0,
             "largest spring extension, fraction of rest")
        .doc("largest spring extension, fraction of rest length");
    t.boolean("correct_all", &S::correct_all,
              "the over-extension correction holds every spring, as the document does (false: "
              "the structural springs only, so that the sheet shears freely)")
        .doc(
            "the over-extension correction holds every spring, as the document does (false: the "
            "structural springs only)");
    t.number("thickness", &S::thickness, 0.0, 10.0,
             "self-collision distance, m (0 = the ring's wire thickness 2a)")
        .unit("m")
        .doc("self-collision distance (0: the wire thickness 2a)");
    t.number("areal_density", &S::areal_density, 0.0, 1e6,
             "kg/m^2 of rest sheet (0 = each mass weighs one ring)")
        .unit("kg/m²")
        .doc("mass per rest-sheet area (0: each mass weighs one ring)");
    return t;
  }();
  return table;
}

// model settings from the knob fields (substeps dropped) and the scene
massspring::Settings settings_from(const Scene& scene, const Weave& weave,
                                   const MassSpringKnobs& knobs) {
  massspring::Settings s = knobs;
  s.point_mass = scene.ring.mass();
  // self-collision only when the scene asks for it; thickness 0 = the ring's wire thickness 2a
  s.self_collision = scene.self_contact;
  if (s.thickness <= 0.0) s.thickness = scene.ring.wire_diameter();
  // a ring centre stays a wire radius above a surface; a cloth mass a tenth of the thickness, so
  // that the flat triangles between masses do not cut into a curved collider
  s.collision_margin = weave.type == WeaveType::grid ? 0.1 * s.thickness : scene.ring.wire_radius;
  return s;
}

class MassSpringBackend final : public Backend {
 public:
  const char* name() const override { return "massspring"; }

  void reset(const Scene& scene, const Weave& weave, const Knobs& knobs) override {
    const MassSpringKnobs settings = massspring_knobs().settings(knobs);
    sim_.reset(scene, weave, settings_from(scene, weave, settings), knob_value(knobs, "dt"),
               settings.substeps);
  }

  StepStatus step(double dt) override {
    sim_.step(dt);
    return StepStatus::ok;
  }

  void frame(RingFrame& out) const override { sim_.frame(out); }

  const StageProfile& profile() const override { return sim_.profile(); }

 private:
  MassSpringSim sim_;
};

}  // namespace

BackendInfo massspring_backend_info() {
  BackendInfo info;
  info.name = "massspring";
  info.cost_us_per_ring_step = 0.5;
  info.bytes_per_ring = 1000;
  info.cloth_surface = true;
  info.summary =
      "mass-spring cloth: structural/shear/bending springs, damped Verlet, 10 % over-extension "
      "correction, surface-following ring orientation";
  info.knobs = massspring_knobs().specs();
  info.knob_round_trip = massspring_knobs().round_trip();
  info.create = [] { return std::unique_ptr<Backend>(new MassSpringBackend()); };
  return info;
}

}  // namespace chainmail
