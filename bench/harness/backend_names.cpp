#include "bench/harness/backend_names.hpp"

#include "backends/backend.hpp"

namespace chainmail {

std::vector<std::string> built_backend_names() {
  std::vector<std::string> names;
  for (const auto& info : backend_registry()) names.push_back(info.name);
  return names;
}

bool backend_known_unbuilt(const std::string& name) {
  return backend_known(name) && !backend_built(name);
}

std::string join_names(const std::vector<std::string>& names) {
  std::string joined;
  for (const auto& name : names) joined += (joined.empty() ? "" : ", ") + name;
  return joined;
}

}  // namespace chainmail
