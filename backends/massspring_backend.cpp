// placeholder until the massspring backend lands
#include <stdexcept>

#include "backends/backend.hpp"

namespace chainmail {
BackendInfo massspring_backend_info() {
  BackendInfo info;
  info.name = "massspring";
  info.summary = "not built yet";
  info.knobs = {{"dt", KnobSpec::Type::number, 0.001, 1e-7, 1.0, "time step, s"}};
  info.create = []() -> std::unique_ptr<Backend> { throw std::runtime_error("massspring: not built yet"); };
  return info;
}
}  // namespace chainmail
