#include "core/massspring/massspring_sim.hpp"

namespace chainmail {

void MassSpringSim::reset(const Scene& scene, const Weave& weave,
                          const massspring::Settings& settings, double dt, int substeps) {
  weave_ = weave;
  model_ = massspring::make_model(scene, weave_, settings);
  state_ = massspring::make_state(model_, weave_.rest_position);
  substeps_ = substeps > 0 ? substeps : massspring::stable_substeps(model_, dt);
  // the initial velocity as Verlet holds it: the previous position one substep back
  const double h = dt / substeps_;
  for (int m = 0; m < state_.size(); ++m) {
    if (model_.inv_mass[m] > 0.0) state_.previous.col(m) -= h * scene.initial_velocity;
  }
  state_.last_dt = h;
  flip_ = massspring::normal_signs(weave_);
  profile_.clear();
}

void MassSpringSim::step(double dt) {
  const double h = dt / substeps_;
  for (int k = 0; k < substeps_; ++k) massspring::step(model_, state_, h, profile_);
}

void MassSpringSim::frame(RingFrame& out) const {
  const int n = state_.size();
  out.resize(n);
  out.t = state_.t;
  out.position = state_.position;
  for (int m = 0; m < n; ++m) out.velocity.col(m) = state_.velocity(m);
  massspring::surface_orientations(state_.position, weave_, flip_, out.orientation);
}

}  // namespace chainmail
