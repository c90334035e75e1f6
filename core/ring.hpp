// Ring geometry: a torus with wire (tube) radius a and centre-line radius c.
// Local frame: the ring lies in the local X/Z plane, its axis (normal) is local +Y.
#pragma once

#include <cstdint>
#include <vector>

#include "core/types.hpp"

namespace chainmail {

struct RingGeometry {
  double wire_radius = 0.0008;    // a, m
  double centre_radius = 0.0048;  // c, m (centre of ring to centre of wire)
  double density = 7850.0;        // kg/m^3

  // armourers' names: wire diameter WD = 2a, inner diameter ID = 2(c - a), AR = ID / WD
  static RingGeometry from_diameters(double wire_diameter, double inner_diameter, double density);
  double wire_diameter() const { return 2.0 * wire_radius; }
  double inner_diameter() const { return 2.0 * (centre_radius - wire_radius); }
  double aspect_ratio() const { return inner_diameter() / wire_diameter(); }

  // largest centre distance of two linked rings, 2(c - a) = ID
  double max_link_distance() const { return inner_diameter(); }
  // smallest centre distance the paper allows between neighbours: the wire thickness 2a
  double min_link_distance() const { return 2.0 * wire_radius; }

  double volume() const;  // 2 pi^2 c a^2, m^3
  double mass() const;    // kg
  // principal moments of inertia about the centre, local axes (x, y, z) with y the ring axis; kg
  // m^2
  Vec3 inertia() const;
};

// point on the ring's centre circle at angle s, in world space
Vec3 centre_circle_point(const Vec3& centre, const Quat& orientation, double c, double s);
// ring normal (local +Y) in world space
inline Vec3 ring_axis(const Quat& orientation) {
  return orientation * Vec3::UnitY();
}

// the ring's surface as triangles in its local frame, for drawing and for exported meshes:
// `around` segments along the ring (u), `across` around the wire (v); the seams are duplicated so
// that indices stay simple
struct RingSurface {
  std::vector<float> position;       // (3 * vertices) m
  std::vector<float> normal;         // (3 * vertices) unit, outward
  std::vector<std::uint32_t> index;  // (3 * triangles) counter-clockwise seen from outside
  int vertices() const { return static_cast<int>(position.size() / 3); }
};
RingSurface ring_surface(double wire_radius, double centre_radius, int around, int across);

}  // namespace chainmail
