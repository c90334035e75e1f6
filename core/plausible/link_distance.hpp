// How far apart can the centres of two linked rings be, given their relative orientation? (The
// question the plausible model's paper leaves open, §6.1.) Two rings are linked when each circle
// crosses the other's disk once, and clear when their centre circles stay 2a apart (the exact
// torus contact of circle_contact.hpp); for a fixed orientation of both rings relative to the
// line through their centres, the largest centre distance at which they are both is where the
// wires hook: one number per orientation, tabulated below for models that need a link length.
#pragma once

#include <vector>

#include "core/ring.hpp"
#include "core/types.hpp"
#include "core/weave.hpp"

namespace chainmail {

// the orientation of two rings relative to the line through their centres, up to a turn about
// that line and a mirror image (all the distance depends on). Each axis's sign is chosen to point
// along the line (a ring is the same ring turned over).
struct LinkOrientation {
  // rad, [0, pi/2]: the angle between a ring's axis and the plane normal to the centre line
  // (0: the line lies in the ring's plane, the hook of a straight chain; pi/2: the ring faces the
  // other)
  double tilt_first = 0.0;
  double tilt_second = 0.0;
  // rad, [0, pi]: the angle about the centre line between the two axes' parts normal to it (pi/2:
  // the rings turned a quarter turn from each other, as in a chain)
  double twist = 0.0;
};

// the relative orientation of rings with these axes (unit) and centres along `centre_line`
// (second minus first, any length > 0)
LinkOrientation link_orientation(const Vec3& axis_first, const Vec3& axis_second,
                                 const Vec3& centre_line);

// ring axes and centre line (along x, first ring at the origin) that have this orientation
void link_axes(const LinkOrientation& orientation, Vec3& axis_first, Vec3& axis_second);

// the largest centre distance (m) at which two rings of this geometry with this orientation are
// linked and clear of each other; 0 when no distance is both. Exact to round-off: the linked and
// clear distances are scanned in steps of c/64 from 0 to 2c + 2a and the last boundary is bisected
// (an interval of linked, clear distances narrower than a step can be missed).
double max_link_distance(const LinkOrientation& orientation, const RingGeometry& ring);

// max_link_distance on a regular grid over the orientations, interpolated between the nodes
// (trilinear, so a node with no linked distance, 0, pulls its neighbourhood towards 0)
class LinkDistanceTable {
 public:
  // nodes per axis: tilts over [0, pi/2], twist over [0, pi]; at least 2 each
  LinkDistanceTable(const RingGeometry& ring, int tilt_nodes = 7, int twist_nodes = 13);

  double max_distance(const LinkOrientation& orientation) const;  // m
  // the same for rings with these axes along this centre line (see link_orientation)
  double max_distance(const Vec3& axis_first, const Vec3& axis_second,
                      const Vec3& centre_line) const;

  int tilt_nodes() const { return tilt_nodes_; }
  int twist_nodes() const { return twist_nodes_; }
  // the node (i, j, k): tilt_first index i, tilt_second j, twist k
  LinkOrientation node(int i, int j, int k) const;
  double at(int i, int j, int k) const { return value_[(i * tilt_nodes_ + j) * twist_nodes_ + k]; }

 private:
  int tilt_nodes_, twist_nodes_;
  std::vector<double> value_;  // (tilt x tilt x twist) m
};

// The plausible model's link length: the same largest centre distance for rings given by their
// axes, and for a weave's neighbours as the model turns them (chain, 4-in-1).

// the largest centre distance d <= ID at which a ring at the origin with unit axis `first` and
// one at d * direction with unit axis `second` are linked with their tori not interpenetrating
// (centre circles at least 2a apart); 0 when no such distance exists (rings turned nearly into
// one plane, like 4-in-1 neighbours at the paper's swivel, cannot link without touching). m
double exact_max_link_distance(const RingGeometry& ring, const Vec3& first, const Vec3& second,
                               const Vec3& direction);

// the largest length of a 4-in-1 link whose rings lean by +-lean about the sheet's row normal
// (the advance direction), the link at angle alpha from the row within the sheet: the reach
// shrinks as the link turns toward the row, where the leaning rings face each other. 0 when the
// geometry gives none. m
double four_in_one_link_reach(const RingGeometry& ring, double lean, double alpha);
// rad, the angle of a 4-in-1 link from its row in the weave's rest layout (half a ring along the
// row, one row on)
double four_in_one_rest_link_angle();

// the largest link length of a weave's neighbours as the plausible model turns them at full
// extension: a chain's perpendicular rings; 4-in-1 neighbours swivelled by +-`extended_swivel`
// about their row normal, placed as the rest layout places them; 0 when the geometry gives none
// (and for a plain grid). m
double weave_max_link_distance(const Weave& weave, const RingGeometry& ring,
                               double extended_swivel);

}  // namespace chainmail
