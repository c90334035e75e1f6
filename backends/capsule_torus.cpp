#include "backends/capsule_torus.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace chainmail {

CapsuleTorus capsule_torus(double wire_radius, double centre_radius, int pieces) {
  const double half_angle = std::numbers::pi / pieces;
  CapsuleTorus torus;
  torus.pieces = pieces;
  // balance: vertex_radius - c = c - vertex_radius cos(pi / N)
  torus.vertex_radius = 2.0 * centre_radius / (1.0 + std::cos(half_angle));
  torus.midpoint_radius = torus.vertex_radius * std::cos(half_angle);
  torus.capsule_length = 2.0 * torus.vertex_radius * std::sin(half_angle);
  // the compound is the polygon swept by a ball of radius a, the torus the circle swept by it:
  // their surfaces are as far apart as the polygon is from the circle
  torus.surface_error =
      std::max(torus.vertex_radius - centre_radius, centre_radius - torus.midpoint_radius);
  // inner diameter along a line through the centre: opposite sides of the polygon less the wire
  const double id = 2.0 * (centre_radius - wire_radius);
  if (pieces % 2 == 0) {
    torus.inner_diameter_min = 2.0 * torus.midpoint_radius - 2.0 * wire_radius;
    torus.inner_diameter_max = 2.0 * torus.vertex_radius - 2.0 * wire_radius;
  } else {
    // a vertex faces a chord midpoint; the sum is smallest a quarter piece off
    torus.inner_diameter_min =
        2.0 * torus.midpoint_radius / std::cos(0.5 * half_angle) - 2.0 * wire_radius;
    torus.inner_diameter_max = torus.vertex_radius + torus.midpoint_radius - 2.0 * wire_radius;
  }
  torus.inner_diameter_error =
      std::max(std::abs(torus.inner_diameter_min - id), std::abs(torus.inner_diameter_max - id));
  return torus;
}

}  // namespace chainmail
