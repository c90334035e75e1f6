#include <cmath>
#include <set>
#include <sstream>

#include "backends/backend.hpp"

namespace chainmail {

BackendInfo plausible_backend_info();
BackendInfo massspring_backend_info();
#if CHAINMAIL_HAVE_BULLET
BackendInfo bullet_backend_info();
#endif
#if CHAINMAIL_HAVE_ODE
BackendInfo ode_backend_info();
#endif

const std::vector<BackendInfo>& backend_registry() {
  static const std::vector<BackendInfo> registry = [] {
    std::vector<BackendInfo> all;
    all.push_back(plausible_backend_info());
    all.push_back(massspring_backend_info());
#if CHAINMAIL_HAVE_BULLET
    all.push_back(bullet_backend_info());
#endif
#if CHAINMAIL_HAVE_ODE
    all.push_back(ode_backend_info());
#endif
    return all;
  }();
  return registry;
}

const BackendInfo* find_backend(const std::string& name) {
  for (const auto& info : backend_registry()) {
    if (info.name == name) return &info;
  }
  return nullptr;
}

Knobs resolve_knobs(const Scene& scene, const BackendInfo& backend) {
  Knobs knobs;
  for (const auto& spec : backend.knobs) knobs[spec.name] = spec.default_value;
  const auto it = scene.backends.find(backend.name);
  if (it == scene.backends.end()) return knobs;
  const std::string prefix = scene.file + ": key 'backends." + backend.name;
  if (!it->is_object()) throw SceneError(prefix + "': must be an object");
  for (auto knob = it->begin(); knob != it->end(); ++knob) {
    const std::string key = prefix + "." + knob.key() + "'";
    const KnobSpec* spec = nullptr;
    for (const auto& s : backend.knobs) {
      if (s.name == knob.key()) spec = &s;
    }
    if (!spec) {
      std::string known;
      for (const auto& s : backend.knobs) known += (known.empty() ? "" : ", ") + s.name;
      throw SceneError(key + ": unknown knob (known: " + known + ")");
    }
    double value = 0.0;
    switch (spec->type) {
      case KnobSpec::Type::boolean:
        if (!knob->is_boolean()) throw SceneError(key + ": must be true or false");
        value = knob->get<bool>() ? 1.0 : 0.0;
        break;
      case KnobSpec::Type::integer:
        if (!knob->is_number_integer()) throw SceneError(key + ": must be an integer");
        value = static_cast<double>(knob->get<long long>());
        break;
      case KnobSpec::Type::number:
        if (!knob->is_number()) throw SceneError(key + ": must be a number");
        value = knob->get<double>();
        break;
    }
    if (!std::isfinite(value) || value < spec->min || value > spec->max) {
      std::ostringstream msg;
      msg << key << ": must be in [" << spec->min << ", " << spec->max << "], got " << value;
      throw SceneError(msg.str());
    }
    knobs[spec->name] = value;
  }
  return knobs;
}

void validate_backend_knobs(const Scene& scene) {
  for (auto it = scene.backends.begin(); it != scene.backends.end(); ++it) {
    const BackendInfo* info = find_backend(it.key());
    if (!info) {
      std::string known;
      for (const auto& b : backend_registry()) known += (known.empty() ? "" : ", ") + b.name;
      throw SceneError(scene.file + ": key 'backends." + it.key() +
                       "': unknown backend (known: " + known + ")");
    }
    resolve_knobs(scene, *info);
  }
  if (!find_backend(scene.reference)) {
    throw SceneError(scene.file + ": key 'reference': unknown backend '" + scene.reference + "'");
  }
}

}  // namespace chainmail
