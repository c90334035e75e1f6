// The backend registry: the one list of backends the project has, which of them this binary was
// built with, and their knobs resolved from a scene.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "backends/backend.hpp"

// whether an optional backend is built: 0 or 1, defined by backends/CMakeLists.txt
#ifndef CHAINMAIL_HAVE_BULLET
#define CHAINMAIL_HAVE_BULLET 0
#endif
#ifndef CHAINMAIL_HAVE_ODE
#define CHAINMAIL_HAVE_ODE 0
#endif

// Every backend the project has, in the order the harness lists them: its name and whether this
// binary has it. A built backend is described by <name>_backend_info(), defined in its adapter.
// A new backend needs its adapter, its sources in backends/CMakeLists.txt and one line here.
#define CHAINMAIL_BACKENDS(X)      \
  X(plausible, 1)                  \
  X(massspring, 1)                 \
  X(bullet, CHAINMAIL_HAVE_BULLET) \
  X(ode, CHAINMAIL_HAVE_ODE)       \
  X(torus_xpbd, 1)

namespace chainmail {

#define CHAINMAIL_DECLARE_INFO(name, built) BackendInfo name##_backend_info();
CHAINMAIL_BACKENDS(CHAINMAIL_DECLARE_INFO)
#undef CHAINMAIL_DECLARE_INFO

namespace {

struct Registry {
  std::vector<std::string> known;  // every backend, built or not
  std::vector<BackendInfo> built;  // those in this binary, in the same order
};

const Registry& registry() {
  static const Registry all = [] {
    Registry r;
    // an unbuilt backend's info call sits in a discarded statement, which needs no definition
#define CHAINMAIL_REGISTER(name, is_built) \
  r.known.push_back(#name);                \
  if constexpr (is_built) r.built.push_back(name##_backend_info());
    CHAINMAIL_BACKENDS(CHAINMAIL_REGISTER)
#undef CHAINMAIL_REGISTER
    return r;
  }();
  return all;
}

std::vector<std::string> knob_names(const BackendInfo& backend) {
  std::vector<std::string> names;
  for (const auto& spec : backend.knobs) names.push_back(spec.name);
  return names;
}

// the given value's JSON kind fits the knob's type; throws SceneError naming `key`
void check_kind(const KnobSpec& spec, const KnobValue& given, const std::string& key) {
  using Kind = KnobValue::Kind;
  switch (spec.type) {
    case KnobSpec::Type::boolean:
      if (given.kind != Kind::boolean) throw SceneError(key + ": must be true or false");
      break;
    case KnobSpec::Type::integer:
      if (given.kind != Kind::integer) throw SceneError(key + ": must be an integer");
      break;
    case KnobSpec::Type::number:
      if (given.kind != Kind::number && given.kind != Kind::integer) {
        throw SceneError(key + ": must be a number");
      }
      break;
  }
}

}  // namespace

const std::vector<BackendInfo>& backend_registry() { return registry().built; }

const std::vector<std::string>& known_backend_names() { return registry().known; }

bool backend_known(const std::string& name) {
  const auto& known = known_backend_names();
  return std::find(known.begin(), known.end(), name) != known.end();
}

bool backend_built(const std::string& name) { return find_backend(name) != nullptr; }

const BackendInfo* find_backend(const std::string& name) {
  for (const auto& info : backend_registry()) {
    if (info.name == name) return &info;
  }
  return nullptr;
}

const KnobSpec* find_knob(const BackendInfo& backend, const std::string& name) {
  for (const auto& spec : backend.knobs) {
    if (spec.name == name) return &spec;
  }
  return nullptr;
}

Knobs resolve_knobs(const Scene& scene, const BackendInfo& backend) {
  Knobs knobs;
  for (const auto& spec : backend.knobs) knobs[spec.name] = spec.default_value;
  const auto it = scene.backends.find(backend.name);
  if (it == scene.backends.end()) return knobs;
  const std::string prefix = scene.file + ": key 'backends." + backend.name;
  for (const auto& [name, given] : it->second) {
    const std::string key = prefix + "." + name + "'";
    const KnobSpec* spec = find_knob(backend, name);
    if (!spec) {
      throw SceneError(key + ": unknown knob (known: " + join_names(knob_names(backend)) + ")");
    }
    check_kind(*spec, given, key);
    const double value = given.value;
    if (!std::isfinite(value) || value < spec->min || value > spec->max) {
      std::ostringstream msg;
      msg << key << ": must be in [" << spec->min << ", " << spec->max << "], got " << value;
      throw SceneError(msg.str());
    }
    knobs[spec->name] = value;
  }
  return knobs;
}

std::vector<std::string> validate_backend_knobs(const Scene& scene) {
  std::vector<std::string> notes;
  for (const auto& [name, section] : scene.backends) {
    if (!backend_known(name)) {
      throw SceneError(scene.file + ": key 'backends." + name + "': unknown backend (known: " +
                       join_names(known_backend_names()) + ")");
    }
    if (const BackendInfo* info = find_backend(name)) {
      resolve_knobs(scene, *info);
    } else {
      notes.push_back("backends." + name +
                      ": not built into this binary, its knobs are not checked");
    }
  }
  if (!backend_known(scene.reference)) {
    throw SceneError(scene.file + ": key 'reference': unknown backend '" + scene.reference + "'");
  }
  return notes;
}

std::vector<std::string> built_backend_names() {
  std::vector<std::string> names;
  for (const auto& info : backend_registry()) names.push_back(info.name);
  return names;
}

bool backend_known_unbuilt(const std::string& name) {
  return backend_known(name) && !backend_built(name);
}

std::string join_names(const std::vector<std::string>& names) {
  std::string text;
  for (const auto& name : names) text += (text.empty() ? "" : ", ") + name;
  return text;
}

}  // namespace chainmail
