// The mass-spring model behind the interface every model has (reset, void step(double dt),
// frame, model, state, profile): the step of dt in the substeps that keep the springs stable.
#pragma once

#include <cstdint>
#include <vector>

#include "core/frame.hpp"
#include "core/massspring/massspring.hpp"
#include "core/profile.hpp"
#include "core/scene.hpp"
#include "core/weave.hpp"

namespace chainmail {

class MassSpringSim {
 public:
  // at rest in the weave's layout, free masses moving at the scene's initial velocity; dt: the
  // step the caller takes (s); substeps: Verlet steps per step, 0 = the fewest that keep the
  // springs stable at dt (massspring::stable_substeps)
  void reset(const Scene& scene, const Weave& weave, const massspring::Settings& settings,
             double dt, int substeps);
  void step(double dt);
  void frame(RingFrame& out) const;

  const massspring::Model& model() const { return model_; }
  const massspring::State& state() const { return state_; }
  const StageProfile& profile() const { return profile_; }
  int substeps() const { return substeps_; }

 private:
  Weave weave_;
  massspring::Model model_;
  massspring::State state_;
  std::vector<std::int8_t> flip_;  // (n) normal sign that matches the rest layout
  int substeps_ = 1;
  StageProfile profile_;
};

}  // namespace chainmail
