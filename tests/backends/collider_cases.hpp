// Scene pieces shared by the backend tests.
#pragma once

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <vector>

#include "core/frame.hpp"
#include "core/profile.hpp"

namespace chainmail::test {

// one collider of each type, every one with its top surface at height `top` (m) under the origin
inline std::vector<nlohmann::json> colliders_with_top_at(double top) {
  return {
      {{"type", "plane"}, {"point", {0.0, top, 0.0}}},
      {{"type", "sphere"}, {"center", {0.0, top - 0.05, 0.0}}, {"radius", 0.05}},
      {{"type", "box"}, {"center", {0.0, top - 0.02, 0.0}}, {"half_extents", {0.05, 0.02, 0.05}}},
      {{"type", "cylinder"},
       {"center", {0.0, top - 0.02, 0.0}},
       {"radius", 0.05},
       {"half_height", 0.02}}};
}

// one ring dropped 1 cm onto a collider whose top is at `top`: it fell and stopped on it, and the
// backend ran its colliders stage
inline void expect_ring_resting_on(const RingFrame& frame, const StageProfile& profile, double top,
                                   const nlohmann::json& collider) {
  const double y = frame.position(1, 0);
  EXPECT_GT(y, top) << collider["type"];
  EXPECT_LT(y, top + 0.005) << collider["type"];
  EXPECT_LT(frame.velocity.col(0).norm(), 0.02) << collider["type"];
  EXPECT_TRUE(profile.stages().count("colliders")) << collider["type"];
}

}  // namespace chainmail::test
