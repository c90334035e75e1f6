// The one interface every simulation model is driven through.
// reset(scene) builds the model from the scene and the shared rest layout; step(dt) advances it
// (the runner times nothing else); frame() emits the common RingFrame.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/frame.hpp"
#include "core/profile.hpp"
#include "core/scene.hpp"
#include "core/weave.hpp"

namespace chainmail {

// one tunable of a backend, as it appears under backends.<name> in the scene file
struct KnobSpec {
  enum class Type { number, integer, boolean };
  std::string name;
  Type type = Type::number;
  double default_value = 0.0;
  double min = 0.0;  // inclusive
  double max = 0.0;  // inclusive
  std::string help;
};

// resolved knob values (booleans as 0/1), every spec'd knob present
using Knobs = std::map<std::string, double>;

class Backend {
 public:
  virtual ~Backend() = default;
  virtual const char* name() const = 0;
  // build the model; `weave` is the shared rest layout (make_weave of the scene), `knobs` resolved
  virtual void reset(const Scene& scene, const Weave& weave, const Knobs& knobs) = 0;
  virtual void step(double dt) = 0;
  virtual void frame(RingFrame& out) const = 0;
  // stages that ran so far (collision, self_contact, ...), for the leave-out-what-is-unneeded rule
  virtual const StageProfile& profile() const = 0;
};

struct BackendInfo {
  std::string name;
  std::string summary;
  std::vector<KnobSpec> knobs;  // must include "dt"
  bool cloth_surface = false;   // its rings stand for a cloth surface: drawn as a textured mesh
  // rough costs at default knobs, measured on a 2-core machine, for the up-front estimate that
  // refuses runs too large for the budget and announces long reference runs
  double cost_us_per_ring_step = 1.0;  // wall microseconds per ring per step
  double bytes_per_ring = 2048.0;      // peak resident bytes per ring
  std::function<std::unique_ptr<Backend>()> create;
};

// every backend compiled into this binary, in a fixed order
const std::vector<BackendInfo>& backend_registry();
const BackendInfo* find_backend(const std::string& name);  // nullptr when unknown
// knob values for `backend` from scene.backends[backend] over the defaults; throws SceneError
// naming the key for unknown knobs, wrong types and out-of-range values
Knobs resolve_knobs(const Scene& scene, const BackendInfo& backend);
// check every backends.<name> object of the scene (unknown backend names too); throws SceneError
void validate_backend_knobs(const Scene& scene);

}  // namespace chainmail
