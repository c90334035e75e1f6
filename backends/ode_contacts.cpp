// ODE rigid-torus backend: one solver step's collision pipeline. A broad phase over one bounding
// sphere per ring, a mid phase that keeps the capsules of a ring near the other ring's wire, then
// capsule against capsule (or collider), with duplicate contacts merged, then QuickStep.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "backends/ode_backend.hpp"

namespace chainmail::ode {
namespace {

int ring_of(dBodyID body) {
  return static_cast<int>(reinterpret_cast<std::intptr_t>(dBodyGetData(body)));
}
std::size_t collider_of(dGeomID geom) {
  return static_cast<std::size_t>(reinterpret_cast<std::intptr_t>(dGeomGetData(geom)));
}

}  // namespace

void OdeBackend::solver_step(double h) {
  {
    auto scope = profile_.scope("ring_contact");
    dSpaceCollide(ring_space_, this, &OdeBackend::near_callback);
  }
  if (has_colliders_) {
    auto scope = profile_.scope("colliders");
    dSpaceCollide2(reinterpret_cast<dGeomID>(ring_space_), reinterpret_cast<dGeomID>(static_space_),
                   this, &OdeBackend::near_callback);
  }
  {
    auto scope = profile_.scope("solve");
    // QuickStep shuffles constraints with ODE's global generator: seed it per step so the
    // result depends on this model alone
    dRandSetSeed(static_cast<unsigned long>(solver_steps_++));
    const int ok = dWorldQuickStep(world_, h);
    dJointGroupEmpty(contacts_);
    if (!ok) throw OdeFailure("ode: QuickStep could not allocate memory");
  }
}

void OdeBackend::near_callback(void* data, dGeomID first, dGeomID second) {
  static_cast<OdeBackend*>(data)->collide_pair(first, second);
}

void OdeBackend::collide_pair(dGeomID first, dGeomID second) {
  // a space against a space or a geom: descend into it
  if (dGeomIsSpace(first) || dGeomIsSpace(second)) {
    dSpaceCollide2(first, second, this, &OdeBackend::near_callback);
    return;
  }
  dBodyID body1 = dGeomGetBody(first);
  dBodyID body2 = dGeomGetBody(second);
  if (body1 == body2) return;  // two static geoms
  const bool moves1 = body1 && !dBodyIsKinematic(body1);
  const bool moves2 = body2 && !dBodyIsKinematic(body2);
  if (!moves1 && !moves2) return;  // pinned against pinned or static: nothing to solve

  if (body1 && body2) {
    const int ring1 = ring_of(body1), ring2 = ring_of(body2);
    if (are_neighbours(ring1, ring2)) {
      collide_rings(ring1, ring2);
    } else if (self_contact_) {
      auto scope = profile_.scope("self_contact");
      collide_rings(ring1, ring2);
    }
  } else {
    const int ring = ring_of(body1 ? body1 : body2);
    dGeomID collider = body1 ? second : first;
    collide_ring_with_collider(ring, collider);
  }
}

// pieces of both rings near the other ring's wire, then capsule against capsule
void OdeBackend::collide_rings(int first, int second) {
  near_pieces(first, second, near_first_);
  if (near_first_.empty()) return;
  near_pieces(second, first, near_second_);
  const double reach2 = piece_pair_reach_ * piece_pair_reach_;
  pair_contacts_.clear();
  for (dGeomID p : near_first_) {
    const dReal* pc = dGeomGetPosition(p);
    for (dGeomID q : near_second_) {
      const dReal* qc = dGeomGetPosition(q);
      const double d2 = (pc[0] - qc[0]) * (pc[0] - qc[0]) + (pc[1] - qc[1]) * (pc[1] - qc[1]) +
                        (pc[2] - qc[2]) * (pc[2] - qc[2]);
      if (d2 > reach2) continue;
      dContactGeom found[kMaxContactsLimit];
      const int count = dCollide(p, q, settings_.max_contacts, found, sizeof(dContactGeom));
      pair_contacts_.insert(pair_contacts_.end(), found, found + count);
    }
  }
  merge_duplicate_contacts(pair_contacts_);
  for (const dContactGeom& geom : pair_contacts_) {
    add_contact(geom, bodies_[first], bodies_[second], ring_friction_);
  }
}

// where two wires touch near a polygon vertex, both capsules of each ring report the same
// touch: keep the deepest contact of every cluster closer than half a wire radius. Redundant
// rows only slow QuickStep down and make its forces jitter.
void OdeBackend::merge_duplicate_contacts(std::vector<dContactGeom>& contacts) const {
  std::stable_sort(contacts.begin(), contacts.end(),
                   [](const dContactGeom& x, const dContactGeom& y) { return x.depth > y.depth; });
  const double radius2 = 0.25 * wire_radius_internal_ * wire_radius_internal_;
  std::size_t kept = 0;
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    bool duplicate = false;
    for (std::size_t j = 0; j < kept && !duplicate; ++j) {
      double d2 = 0.0;
      for (int axis = 0; axis < 3; ++axis) {
        const double d = contacts[k].pos[axis] - contacts[j].pos[axis];
        d2 += d * d;
      }
      duplicate = d2 < radius2;
    }
    if (!duplicate) contacts[kept++] = contacts[k];
  }
  contacts.resize(kept);
}

// the pieces of `ring` whose centres lie within piece_reach_ of the centre circle of `other`
void OdeBackend::near_pieces(int ring, int other, std::vector<dGeomID>& out) const {
  out.clear();
  const dReal* centre = dBodyGetPosition(bodies_[other]);
  const dReal* rotation = dBodyGetRotation(bodies_[other]);  // row-major 3x4
  const Vec3 axis(rotation[1], rotation[5], rotation[9]);    // local Y: the ring axis
  const Vec3 c(centre[0], centre[1], centre[2]);
  const double reach2 = piece_reach_ * piece_reach_;
  const std::size_t begin = static_cast<std::size_t>(ring) * settings_.pieces;
  for (std::size_t k = begin; k < begin + settings_.pieces; ++k) {
    const dReal* m = dGeomGetPosition(pieces_[k]);
    const Vec3 d = Vec3(m[0], m[1], m[2]) - c;
    const double height = d.dot(axis);
    const double radial = std::sqrt(std::max(0.0, d.squaredNorm() - height * height));
    const double off = radial - centre_radius_internal_;
    if (height * height + off * off <= reach2) out.push_back(pieces_[k]);
  }
}

// every piece of `ring` whose box meets the collider's box
void OdeBackend::collide_ring_with_collider(int ring, dGeomID collider) {
  dReal box[6];  // min x, max x, min y, max y, min z, max z
  dGeomGetAABB(collider, box);
  const double friction = collider_friction_[collider_of(collider)];
  const std::size_t begin = static_cast<std::size_t>(ring) * settings_.pieces;
  const double half = 0.5 * piece_pair_reach_;  // half chord + a
  for (std::size_t k = begin; k < begin + settings_.pieces; ++k) {
    const dReal* m = dGeomGetPosition(pieces_[k]);
    bool overlaps = true;
    for (int axis = 0; axis < 3; ++axis) {
      overlaps &= m[axis] + half >= box[2 * axis] && m[axis] - half <= box[2 * axis + 1];
    }
    if (overlaps) add_contacts(pieces_[k], collider, friction);
  }
}

void OdeBackend::add_contacts(dGeomID first, dGeomID second, double friction) {
  dContactGeom found[kMaxContactsLimit];
  const int count = dCollide(first, second, settings_.max_contacts, found, sizeof(dContactGeom));
  for (int k = 0; k < count; ++k) {
    add_contact(found[k], dGeomGetBody(first), dGeomGetBody(second), friction);
  }
}

// one contact joint; `geom.normal` points from body2 into body1, as dCollide reports it
void OdeBackend::add_contact(const dContactGeom& geom, dBodyID body1, dBodyID body2,
                             double friction) {
  dContact contact{};
  contact.geom = geom;
  dSurfaceParameters& surface = contact.surface;
  surface.mode = dContactApprox1 | dContactSoftERP | dContactSoftCFM;
  surface.mu = friction;
  surface.soft_erp = settings_.erp;
  surface.soft_cfm = settings_.cfm;
  if (settings_.restitution > 0.0) {
    surface.mode |= dContactBounce;
    surface.bounce = settings_.restitution;
    surface.bounce_vel = 0.0;
  }
  dJointID joint = dJointCreateContact(world_, contacts_, &contact);
  dJointAttach(joint, body1, body2);
}

bool OdeBackend::are_neighbours(int a, int b) const {
  const auto& around = neighbours_[a];
  return std::find(around.begin(), around.end(), b) != around.end();
}

}  // namespace chainmail::ode
