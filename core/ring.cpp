#include "core/ring.hpp"

#include <numbers>

namespace chainmail {

RingGeometry RingGeometry::from_diameters(double wire_diameter, double inner_diameter,
                                          double density) {
  RingGeometry ring;
  ring.wire_radius = 0.5 * wire_diameter;
  ring.centre_radius = 0.5 * inner_diameter + ring.wire_radius;
  ring.density = density;
  return ring;
}

double RingGeometry::volume() const {
  return 2.0 * std::numbers::pi * std::numbers::pi * centre_radius * wire_radius * wire_radius;
}

double RingGeometry::mass() const {
  return density * volume();
}

Vec3 RingGeometry::inertia() const {
  // solid torus: about its axis m (c^2 + 3/4 a^2), about a diameter m (c^2 / 2 + 5/8 a^2)
  const double m = mass();
  const double c2 = centre_radius * centre_radius;
  const double a2 = wire_radius * wire_radius;
  const double diameter = m * (0.5 * c2 + 0.625 * a2);
  return Vec3(diameter, m * (c2 + 0.75 * a2), diameter);
}

Vec3 centre_circle_point(const Vec3& centre, const Quat& orientation, double c, double s) {
  return centre + orientation * Vec3(c * std::cos(s), 0.0, c * std::sin(s));
}

}  // namespace chainmail
