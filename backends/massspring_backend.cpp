// The cloth document's mass-spring model as a chainmail backend: one point mass per ring, and ring
// orientations that follow the cloth surface with no swivel (the "cloth + texture" baseline).
#include <cmath>

#include "backends/backend.hpp"
#include "core/massspring.hpp"

namespace chainmail {
namespace {

// model settings from resolved knobs and the scene
massspring::Settings settings_from(const Scene& scene, const Weave& weave, const Knobs& knobs) {
  massspring::Settings s;
  s.ks = knobs.at("ks");
  s.shear_ks = knobs.at("shear_ks");
  s.bend_ks = knobs.at("bend_ks");
  s.damping_percent = knobs.at("damping_percent");
  s.damp_rigid = knobs.at("damp_rigid") != 0.0;
  s.correction_passes = static_cast<int>(knobs.at("correction_passes"));
  s.max_extension = knobs.at("max_extension");
  s.areal_density = knobs.at("areal_density");
  s.point_mass = scene.ring.mass();
  // self-collision only when the scene asks for it; thickness 0 = the ring's wire thickness 2a
  s.self_collision = scene.self_contact;
  s.thickness = knobs.at("thickness") > 0.0 ? knobs.at("thickness") : scene.ring.wire_diameter();
  // a ring centre stays a wire radius above a surface; a cloth mass a tenth of the thickness, so
  // that the flat triangles between masses do not cut into a curved collider
  s.collision_margin = weave.type == WeaveType::grid ? 0.1 * s.thickness : scene.ring.wire_radius;
  return s;
}

class MassSpringBackend final : public Backend {
 public:
  const char* name() const override { return "massspring"; }

  void reset(const Scene& scene, const Weave& weave, const Knobs& knobs) override {
    weave_ = weave;
    model_ = massspring::make_model(scene, weave_, settings_from(scene, weave_, knobs));
    state_ = massspring::make_state(model_, weave_.rest_position);
    substeps_ = static_cast<int>(knobs.at("substeps"));
    // the scene's initial velocity, as Verlet holds it: the previous position one step back
    const double h = knobs.at("dt") / substeps_;
    for (int m = 0; m < state_.size(); ++m) {
      if (model_.inv_mass[m] > 0.0) state_.previous.col(m) -= h * scene.initial_velocity;
    }
    state_.last_dt = h;
    flip_ = massspring::normal_signs(weave_);
    profile_.clear();
  }

  void step(double dt) override {
    const double h = dt / substeps_;
    for (int k = 0; k < substeps_; ++k) massspring::step(model_, state_, h, profile_);
  }

  void frame(RingFrame& out) const override {
    const int n = state_.size();
    out.resize(n);
    out.t = state_.t;
    out.position = state_.position;
    for (int m = 0; m < n; ++m) out.velocity.col(m) = state_.velocity(m);
    massspring::surface_orientations(state_.position, weave_, flip_, out.orientation);
  }

  const StageProfile& profile() const override { return profile_; }

 private:
  Weave weave_;
  massspring::Model model_;
  massspring::State state_;
  std::vector<std::int8_t> flip_;  // (n) normal sign that matches the rest layout
  int substeps_ = 1;
  StageProfile profile_;
};

}  // namespace

BackendInfo massspring_backend_info() {
  using T = KnobSpec::Type;
  BackendInfo info;
  info.name = "massspring";
  info.cost_us_per_ring_step = 0.5;
  info.bytes_per_ring = 1000;
  info.cloth_surface = true;
  info.summary =
      "mass-spring cloth: structural/shear/bending springs, damped Verlet, 10 % over-extension "
      "correction, surface-following ring orientation";
  info.knobs = {
      {"dt", T::number, 1.0 / 2700.0, 1e-7, 0.1, "time step, s (90 frames/s x 30 steps)"},
      {"substeps", T::integer, 1, 1, 1000, "Verlet steps per dt"},
      {"ks", T::number, 5000.0, 0.0, 1e9, "structural spring constant, N/m"},
      {"shear_ks", T::number, 5000.0, 0.0, 1e9, "shear spring constant, N/m"},
      {"bend_ks", T::number, 1000.0, 0.0, 1e9, "bending spring constant, N/m"},
      {"damping_percent", T::number, 0.2, 0.0, 100.0,
       "Verlet damping, percent per 1/2700 s (the document's step) of motion other than rigid"},
      {"damp_rigid", T::boolean, 0.0, 0.0, 1.0,
       "damping slows all motion, rigid motion included (the document's drag)"},
      {"correction_passes", T::integer, 1, 0, 10000,
       "over-extension correction passes per step (0 = off)"},
      {"max_extension", T::number, 0.1, 0.0, 10.0, "largest spring extension, fraction of rest"},
      {"thickness", T::number, 0.0, 0.0, 10.0,
       "self-collision distance, m (0 = the ring's wire thickness 2a)"},
      {"areal_density", T::number, 0.0, 0.0, 1e6,
       "kg/m^2 of rest sheet (0 = each mass weighs one ring)"},
  };
  info.create = [] { return std::unique_ptr<Backend>(new MassSpringBackend()); };
  return info;
}

}  // namespace chainmail
