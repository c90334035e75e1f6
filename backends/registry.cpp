// The backend registry: the one list of backends the project has, which of them this binary was
// built with, and their knobs resolved from a scene.
#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>

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
// A new backend of the project needs its adapter, its sources in backends/CMakeLists.txt and one
// line here; code outside the project calls register_backend() instead.
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
  std::deque<BackendInfo> built;   // those in this binary, in the same order (a deque: pointers
                                   // into it survive register_backend)
};

Registry& registry() {
  static Registry all = [] {
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
    case KnobSpec::Type::choice:
      break;  // choice_index says what it must be
  }
}

// a user's text for a message: at most 40 bytes, control characters and non-ASCII as '?'
std::string printable(const std::string& text) {
  std::string out = text.substr(0, 40);
  for (char& c : out)
    if (c < 0x20 || c > 0x7e) c = '?';
  return text.size() > 40 ? out + "..." : out;
}

// the index of a choice knob's given name; throws SceneError naming `key` and every name
double choice_index(const KnobSpec& spec, const KnobValue& given, const std::string& key) {
  if (given.kind == KnobValue::Kind::string) {
    for (std::size_t k = 0; k < spec.choices.size(); ++k)
      if (spec.choices[k] == given.text) return static_cast<double>(k);
  }
  std::string names;
  for (const std::string& name : spec.choices)
    names.append(names.empty() ? "\"" : ", \"").append(name).append("\"");
  std::string got = "a number";
  // appended piece by piece: GCC 12 misreads `"\"" + text` as an overlapping copy
  if (given.kind == KnobValue::Kind::string)
    got = std::string("\"").append(printable(given.text)).append("\"");
  if (given.kind == KnobValue::Kind::boolean) got = given.value != 0.0 ? "true" : "false";
  if (given.kind == KnobValue::Kind::other) got = "another kind of value";
  throw SceneError(key + ": must be one of " + names + ", got " + got);
}

}  // namespace

// the checks of register_backend
namespace {

// a backend or knob name: a word of lowercase letters, digits and '_' starting with a letter
bool plain_word(const std::string& name) {
  if (name.empty() || name[0] < 'a' || name[0] > 'z') return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
  });
}

[[noreturn]] void refuse(const std::string& name, const std::string& what) {
  throw std::invalid_argument("register_backend: backend '" + name + "': " + what);
}

void check_new_name(const std::string& name) {
  if (!plain_word(name) || name == "all" || name == "none") {
    refuse(name,
           "a name is a word of lowercase letters, digits and '_' starting with a letter, "
           "and not 'all' or 'none'");
  }
  if (backend_known(name)) {
    refuse(name, std::string("the name is taken") +
                     (backend_built(name) ? "" : " (by a backend not built into this binary)") +
                     "; taken: " + join_names(known_backend_names()));
  }
}

// a choice knob: distinct plain-word names, range [0, names - 1], an integral default
void check_choices(const std::string& backend, const KnobSpec& spec, bool integral) {
  const std::string knob = "knob '" + spec.name + "': ";
  const std::set<std::string> distinct(spec.choices.begin(), spec.choices.end());
  if (spec.choices.empty() || distinct.size() != spec.choices.size() ||
      !std::all_of(spec.choices.begin(), spec.choices.end(), plain_word))
    refuse(backend, knob + "a choice knob needs distinct names, each a plain lowercase word");
  if (spec.min != 0.0 || spec.max != double(spec.choices.size() - 1) || !integral)
    refuse(backend, knob + "a choice knob has range [0, names - 1] and an integral default");
}

// the knob table rules every backend keeps (the registry's KnobTableContract tests)
void check_new_knobs(const BackendInfo& info) {
  std::set<std::string> names;
  for (const KnobSpec& spec : info.knobs) {
    const std::string knob = "knob '" + spec.name + "': ";
    if (!plain_word(spec.name)) refuse(info.name, knob + "not a plain lowercase word");
    if (!names.insert(spec.name).second) refuse(info.name, knob + "declared twice");
    if (spec.help.empty()) refuse(info.name, knob + "no help text");
    if (!(spec.min <= spec.default_value && spec.default_value <= spec.max))
      refuse(info.name, knob + "default outside [min, max]");
    const bool integral = std::floor(spec.min) == spec.min && std::floor(spec.max) == spec.max &&
                          std::floor(spec.default_value) == spec.default_value;
    if (spec.type == KnobSpec::Type::integer && !integral)
      refuse(info.name, knob + "an integer knob needs integral min, max and default");
    if (spec.type == KnobSpec::Type::boolean && (spec.min != 0.0 || spec.max != 1.0 || !integral))
      refuse(info.name, knob + "a boolean knob has range [0, 1] and default 0 or 1");
    if (spec.type == KnobSpec::Type::choice) check_choices(info.name, spec, integral);
  }
  const KnobSpec* dt = find_knob(info, "dt");
  if (!dt || dt->type != KnobSpec::Type::number || !(dt->min > 0.0))
    refuse(info.name, "needs a knob 'dt' (a number with a positive minimum)");
}

}  // namespace

void register_backend(BackendInfo info) {
  check_new_name(info.name);
  check_new_knobs(info);
  if (!info.create) refuse(info.name, "create is empty");
  Registry& r = registry();
  r.known.push_back(info.name);
  r.built.push_back(std::move(info));
}

const std::deque<BackendInfo>& backend_registry() {
  return registry().built;
}

const std::vector<std::string>& known_backend_names() {
  return registry().known;
}

bool backend_known(const std::string& name) {
  const auto& known = known_backend_names();
  return std::find(known.begin(), known.end(), name) != known.end();
}

bool backend_built(const std::string& name) {
  return find_backend(name) != nullptr;
}

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
    const double value =
        spec->type == KnobSpec::Type::choice ? choice_index(*spec, given, key) : given.value;
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
      throw SceneError(scene.file + ": key 'backends." + name +
                       "': unknown backend (known: " + join_names(known_backend_names()) + ")");
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
