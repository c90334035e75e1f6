// Scene pieces shared by the backend tests.
#pragma once

#include <nlohmann/json.hpp>
#include <vector>

namespace chainmail::test {

// one collider of each type, every one with its top surface at height `top` (m) under the origin
inline std::vector<nlohmann::json> colliders_with_top_at(double top) {
  return {{{"type", "plane"}, {"point", {0.0, top, 0.0}}},
          {{"type", "sphere"}, {"center", {0.0, top - 0.05, 0.0}}, {"radius", 0.05}},
          {{"type", "box"}, {"center", {0.0, top - 0.02, 0.0}}, {"half_extents", {0.05, 0.02, 0.05}}},
          {{"type", "cylinder"},
           {"center", {0.0, top - 0.02, 0.0}},
           {"radius", 0.05},
           {"half_height", 0.02}}};
}

}  // namespace chainmail::test
