// A torus approximated by capsules: the collision shape of a ring in the rigid backends. Pure
// geometry, so that both rigid backends build the same shape and tests can measure its error.
#pragma once

namespace chainmail {

// a torus (wire radius a, centre radius c) approximated by `pieces` capsules of radius a along the
// chords of a regular polygon; the polygon's vertex radius balances the error at the vertices
// (outside the centre circle) against the error at the chord midpoints (inside it)
struct CapsuleTorus {
  int pieces = 0;
  double vertex_radius = 0.0;       // m, polygon vertices from the ring centre
  double midpoint_radius = 0.0;     // m, chord midpoints from the ring centre
  double capsule_length = 0.0;      // m, chord length: distance of a capsule's sphere centres
  double surface_error = 0.0;       // m, largest distance of the compound's surface from the torus
  double inner_diameter_min = 0.0;  // m, inner diameter across opposite chord midpoints
  double inner_diameter_max = 0.0;  // m, inner diameter across opposite vertices
  double inner_diameter_error = 0.0;  // m, largest |inner diameter - ID| over directions
};

CapsuleTorus capsule_torus(double wire_radius, double centre_radius, int pieces);

}  // namespace chainmail
