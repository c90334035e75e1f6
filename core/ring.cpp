#include "core/ring.hpp"

#include <cmath>
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

RingSurface ring_surface(double wire_radius, double centre_radius, int around, int across) {
  RingSurface surface;
  const double a = wire_radius, c = centre_radius;
  // (around + 1) (across + 1) vertices, u around the ring, v around the wire
  for (int i = 0; i <= around; ++i) {
    const double u = 2.0 * std::numbers::pi * i / around;
    for (int k = 0; k <= across; ++k) {
      const double v = 2.0 * std::numbers::pi * k / across;
      const Vec3 normal(std::cos(v) * std::cos(u), std::sin(v), std::cos(v) * std::sin(u));
      const Vec3 position((c + a * std::cos(v)) * std::cos(u), a * std::sin(v),
                          (c + a * std::cos(v)) * std::sin(u));
      for (int axis = 0; axis < 3; ++axis) {
        surface.position.push_back(static_cast<float>(position[axis]));
        surface.normal.push_back(static_cast<float>(normal[axis]));
      }
    }
  }
  // (u, v), (u, v+1), (u+1, v) is counter-clockwise seen from outside the tube
  const int row = across + 1;
  for (int i = 0; i < around; ++i) {
    for (int k = 0; k < across; ++k) {
      const auto p00 = static_cast<std::uint32_t>(i * row + k), p01 = p00 + 1;
      const auto p10 = static_cast<std::uint32_t>(p00 + row), p11 = p10 + 1;
      surface.index.insert(surface.index.end(), {p00, p01, p10, p10, p01, p11});
    }
  }
  return surface;
}

}  // namespace chainmail
