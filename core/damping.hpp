// Damping that leaves rigid motion alone (after Mueller et al. 2007, position based dynamics, 3.5):
// the velocity of every free mass is pulled toward the rigid motion that fits all free masses best,
// so a body falling or turning as a whole keeps its momentum and only its deformation is damped.
// Pins restrict the rigid motions a body can have: none for pins spread over a plane, turning
// about the line of collinear pins, turning about a single pin, any motion without pins.
#pragma once

#include "core/types.hpp"

namespace chainmail {

// per-mass values (masses, inverse masses), kg or 1/kg: a VectorXd or a Map of a std::vector
using MassView = Eigen::Ref<const Eigen::VectorXd>;  // (n)

// the rigid motions the pins leave a body
struct RigidFreedom {
  enum class Kind { free, about_point, about_line, none };
  Kind kind = Kind::free;
  Vec3 point = Vec3::Zero();  // m, a pin (about_point) or a point on the pin line (about_line)
  Vec3 axis = Vec3::UnitY();  // unit, the pin line (about_line)
};

// from the positions of the pinned masses (inverse_mass == 0)
RigidFreedom rigid_freedom(const Positions& position, const MassView& inverse_mass);

// the velocity field v(x) = linear + angular x (x - centre) of a rigid motion
struct RigidMotion {
  Vec3 centre = Vec3::Zero();   // m
  Vec3 linear = Vec3::Zero();   // m/s, velocity at the centre
  Vec3 angular = Vec3::Zero();  // rad/s
  Vec3 at(const Vec3& x) const { return linear + angular.cross(x - centre); }
};

// the allowed rigid motion that fits the velocities of the free masses best (mass-weighted least
// squares; a straight chain gets no spin about its own line); zero when no mass is free
RigidMotion fit_rigid_motion(const RigidFreedom& freedom, const Positions& position,
                             const Positions& velocity, const MassView& mass,
                             const MassView& inverse_mass);

// v_i += fraction * (rigid(x_i) - v_i) for every free mass; fraction in [0, 1]
void damp_toward_rigid(const RigidFreedom& freedom, const Positions& position, const MassView& mass,
                       const MassView& inverse_mass, double fraction, Positions& velocity,
                       int threads = 1);

}  // namespace chainmail
