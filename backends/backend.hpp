// The one interface every simulation model is driven through.
// reset(scene) builds the model from the scene and the shared rest layout; step(dt) advances it
// (the runner times nothing else); frame() emits the common RingFrame.
#pragma once

#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "backends/knobs.hpp"
#include "core/frame.hpp"
#include "core/profile.hpp"
#include "core/scene.hpp"
#include "core/weave.hpp"

namespace chainmail {

// what a step tells the runner: `non_finite` when the model found its state no longer finite
// (it stops advancing; the runner ends the run with verdict non_finite)
enum class StepStatus { ok, non_finite };

class Backend {
 public:
  virtual ~Backend() = default;
  virtual const char* name() const = 0;
  // build the model; `weave` is the shared rest layout (make_weave of the scene), `knobs` resolved
  virtual void reset(const Scene& scene, const Weave& weave, const Knobs& knobs) = 0;
  virtual StepStatus step(double dt) = 0;
  virtual void frame(RingFrame& out) const = 0;
  // stages that ran so far (collision, self_contact, ...), for the leave-out-what-is-unneeded rule
  virtual const StageProfile& profile() const = 0;
  // threads step() may use (at least 1); called before reset. A backend that steps on one thread
  // ignores it. The result of a run must not depend on it (same final-state hash).
  virtual void set_threads(int threads) {}
};

struct BackendInfo {
  std::string name;
  std::string summary;
  std::vector<KnobSpec> knobs;  // must include "dt"; from the backend's KnobTable
  // the KnobTable's binding (resolved knobs -> settings struct -> bound knob values), so that
  // tests check every backend's table through the registry
  std::function<Knobs(const Knobs&)> knob_round_trip;
  bool cloth_surface = false;  // its rings stand for a cloth surface: drawn as a textured mesh
  bool multithreaded = false;  // its step runs on the threads set_threads gives it
  // rough costs at default knobs, measured on a 2-core machine, for the up-front estimate that
  // refuses runs too large for the budget and announces long reference runs
  double cost_us_per_ring_step = 1.0;  // wall microseconds per ring per step
  double bytes_per_ring = 2048.0;      // peak resident bytes per ring
  std::function<std::unique_ptr<Backend>()> create;
};

// Which backends exist and which this binary has. The project has a fixed set of backends
// (plausible, massspring, bullet, ode, torus_xpbd); the optional ones (bullet, ode) are built
// only when the build finds their libraries (CHAINMAIL_WITH_BULLET, CHAINMAIL_WITH_ODE). A name
// that is known but not built is valid input that this binary cannot run; a name that is not
// known is bad input.
// Code outside the project adds its own backends with register_backend(); they follow the
// project's in the order registered, and every command and lookup below treats them alike.

// Adds a backend defined outside this project: after the call it is known and built, scenes may
// configure it under backends.<name> and runs may name it. Call it before anything reads the
// registry (at the start of main); it is not safe against concurrent lookups. BackendInfo
// pointers and references handed out earlier stay valid. Throws std::invalid_argument, with a
// message starting "register_backend: ", when
//   - the name is taken: a backend of this project (built into this binary or not) or one
//     registered before;
//   - the name is not a word of lowercase letters, digits and '_' starting with a letter, or is
//     "all" or "none" (it appears in --backends lists, --set keys and folder names);
//   - the knobs lack "dt" (a number with a positive minimum), repeat a name, have an empty help
//     text, or a default outside its range (integers integral, booleans 0 or 1);
//   - create is empty.
void register_backend(BackendInfo info);

// every backend built into this binary, in the order of known_backend_names(), then the
// registered ones
const std::deque<BackendInfo>& backend_registry();
// every backend the project has, built into this binary or not, in a fixed order, then the
// registered ones
const std::vector<std::string>& known_backend_names();
bool backend_known(const std::string& name);
bool backend_built(const std::string& name);  // known and built into this binary
// names of backend_registry(), in its order
std::vector<std::string> built_backend_names();
// known to the project but not built into this binary (CHAINMAIL_WITH_BULLET=OFF, ...)
bool backend_known_unbuilt(const std::string& name);
// "a, b, c", for messages
std::string join_names(const std::vector<std::string>& names);
const BackendInfo* find_backend(const std::string& name);  // nullptr when unknown or not built
const KnobSpec* find_knob(const BackendInfo& backend, const std::string& name);  // nullptr: none

// knob values for `backend` from scene.backends[backend] over the defaults; throws SceneError
// naming the key for unknown knobs, wrong types and out-of-range values
Knobs resolve_knobs(const Scene& scene, const BackendInfo& backend);

// Checks every backends.<name> section of the scene and the scene's reference. Throws SceneError
// for a name that is not known ("<file>: key 'backends.<name>': unknown backend (known: ...)",
// "<file>: key 'reference': unknown backend '<name>'") and for a bad knob of a built backend.
// A known backend that is not built is not an error: its section is skipped (its knobs cannot be
// checked without its table) and a reference naming it is accepted. Returns one note per skipped
// section, "backends.<name>: not built into this binary, its knobs are not checked", for the
// caller to print once; the same note for the same name in every scene, so notes from several
// scenes can be merged. What to do with a reference that is known but not built (run without
// drape_rms, refuse, pick another) is the caller's decision: test backend_built(scene.reference).
std::vector<std::string> validate_backend_knobs(const Scene& scene);

}  // namespace chainmail
