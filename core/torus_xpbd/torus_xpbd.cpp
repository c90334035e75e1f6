// The rigid-torus XPBD model: set-up, and the step's phases other than contact (those are in
// torus_xpbd_contacts.cpp; the substeps that run them, in torus_xpbd_step.cpp).
#include "core/torus_xpbd/torus_xpbd.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/torus_xpbd/torus_colliders.hpp"

namespace chainmail {
namespace {

// the velocity passes after the first solve the contacts within this many links of a ring that
// touches a collider (table_cloth's drape from Bullet's, 16 x 16, 1 s: 1.70 mm with every contact
// in all 8 passes, 1.96 with only the touching rings', 1.74 with 1 link, 1.74 with 2)
constexpr int kVelocityReach = 2;

// sleeping: a ring whose points all move slower than this for kSleepDelay is put to sleep
constexpr double kSleepSpeed = 1e-3;  // m/s
constexpr double kSleepDelay = 0.3;   // s
bool pair_less(const RingPair& x, const RingPair& y) {
  return x.a != y.a ? x.a < y.a : x.b < y.b;
}

// the pair (a, b) into this step's list, with the seeds it had in the last step's (both lists
// sorted by pair, `cursor` walking the last one)
void carry_pair(int a, int b, std::vector<RingPairContact>& into,
                const std::vector<RingPairContact>& previous, std::size_t& cursor) {
  while (cursor < previous.size() &&
         (previous[cursor].a != a ? previous[cursor].a < a : previous[cursor].b < b))
    ++cursor;
  if (cursor < previous.size() && previous[cursor].a == a && previous[cursor].b == b) {
    into.push_back(previous[cursor]);
  } else {
    RingPairContact fresh;
    fresh.a = a, fresh.b = b;
    into.push_back(fresh);
  }
}

// the two halves: the rings on either side of the median of their rest layout along its longest
// axis across gravity (a hanging sheet splits into left and right, each with its share of the
// pins, and each half's links keep their order outward from the supports)
void split_rings(const Scene& scene, const Weave& weave, TorusXpbdModel& model) {
  const int n = weave.size();
  int down = -1;
  if (scene.gravity.squaredNorm() > 0.0) scene.gravity.cwiseAbs().maxCoeff(&down);
  int axis = 0;
  double widest = -1.0;
  for (int k = 0; k < 3 && n > 0; ++k) {
    if (k == down) continue;
    const double extent =
        weave.rest_position.row(k).maxCoeff() - weave.rest_position.row(k).minCoeff();
    if (extent > widest) widest = extent, axis = k;
  }
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](int x, int y) {
    const double px = weave.rest_position(axis, x), py = weave.rest_position(axis, y);
    return px != py ? px < py : x < y;
  });
  model.part.assign(n, 0);
  for (int k = n / 2; k < n; ++k) model.part[order[k]] = 1;
  for (auto& rings : model.part_rings) rings.clear();
  for (int i = 0; i < n; ++i) model.part_rings[model.part[i]].push_back(i);
}

}  // namespace

TorusXpbdModel make_model(const Scene& scene, const Weave& weave,
                          const TorusXpbdSettings& settings) {
  const int n = weave.size();
  TorusXpbdModel model;
  model.ring = scene.ring;
  model.settings = settings;
  const std::vector<double> mass = ring_masses(scene, weave);
  const Vec3 inertia = scene.ring.inertia() / scene.ring.mass();  // per kg: (diameter, axis, -)
  for (int i = 0; i < n; ++i) {
    model.inverse_mass.push_back(1.0 / mass[i]);
    model.inertia_diameter.push_back(mass[i] * inertia.x());
    model.inertia_axis.push_back(mass[i] * inertia.y());
    model.inverse_inertia_diameter.push_back(1.0 / model.inertia_diameter[i]);
    model.inverse_inertia_axis.push_back(1.0 / model.inertia_axis[i]);
  }
  for (int pinned : resolve_pins(scene, weave)) {
    model.inverse_mass[pinned] = 0.0;
    model.inverse_inertia_diameter[pinned] = model.inverse_inertia_axis[pinned] = 0.0;
  }
  model.links = weave.links;
  std::sort(model.links.begin(), model.links.end(), pair_less);
  model.neighbours = weave.neighbours;
  model.colliders = scene.colliders;
  for (const Collider& collider : scene.colliders)
    model.collider_friction.push_back(settings.friction * collider.friction);
  model.ring_friction = settings.friction * scene.ring_friction;
  model.gravity = scene.gravity;
  model.self_contact = scene.self_contact;
  split_rings(scene, weave, model);
  model.scan_spacing = scene.ring.centre_radius * std::numbers::pi / CirclePairDistance::kSamples;
  return model;
}

void TorusXpbdSim::reset(const Scene& scene, const Weave& weave,
                         const TorusXpbdSettings& settings) {
  model_ = make_model(scene, weave, settings);
  const int n = weave.size();

  // state: the rest layout, free rings at the initial velocity
  state_ = TorusXpbdState{};
  state_.position.resize(n);
  state_.orientation.resize(n);
  state_.velocity.assign(n, Vec3::Zero());
  state_.angular_velocity.assign(n, Vec3::Zero());
  for (int i = 0; i < n; ++i) {
    state_.position[i] = weave.rest_position.col(i);
    const auto q = weave.rest_orientation.col(i);
    state_.orientation[i] = Quat(q(0), q(1), q(2), q(3)).normalized();
    if (model_.inverse_mass[i] > 0.0) state_.velocity[i] = scene.initial_velocity;
  }
  state_.previous_position = state_.position;
  state_.previous_orientation = state_.orientation;
  state_.still_time.assign(n, 0.0);
  state_.asleep.assign(n, 0);
  reset_scratch();
}

// the per-step and per-substep scratch, sized once; linked neighbours are contact pairs for good
void TorusXpbdSim::reset_scratch() {
  const int n = static_cast<int>(state_.position.size());
  rotation_.resize(n);
  for (int i = 0; i < n; ++i) rotation_[i] = state_.orientation[i].toRotationMatrix();
  previous_rotation_ = rotation_;
  reach_.assign(n, 0.0);
  travel_.assign(n, 0.0);
  centres_.resize(3, n);
  link_pairs_.clear();
  for (const RingPair& link : model_.links) {
    RingPairContact pair;
    pair.a = link.a, pair.b = link.b;
    link_pairs_.push_back(pair);
  }
  link_order_.resize(link_pairs_.size());
  for (std::size_t k = 0; k < link_order_.size(); ++k) link_order_[k] = static_cast<int>(k);
  support_depth_.assign(n, -1);
  near_collider_.assign(n, 0);
  queue_.reserve(n);
  touching_.assign(n, 0);
  hash_pairs_.clear();
  other_pairs_.clear();
  previous_pairs_.clear();
  collider_candidates_.clear();
  previous_candidates_.clear();
  for (std::size_t part = 0; part < active_.size(); ++part) active_[part].clear();
  for (std::size_t part = 0; part < collider_holds_.size(); ++part) collider_holds_[part].clear();
  profile_.clear();
}

// candidate pairs and collider candidates for the whole step: whatever the step's motion can
// bring into contact, from a bound on each ring's speed
void TorusXpbdSim::collect_pairs(double dt) {
  auto scope = profile_.scope(stage_name(TorusXpbdStage::collect_pairs));
  const int n = static_cast<int>(state_.position.size());
  const double a = model_.ring.wire_radius, c = model_.ring.centre_radius;
  double& fastest = fastest_;
  fastest = 0.0;
  for (int i = 0; i < n; ++i) {
    reach_[i] = model_.inverse_mass[i] == 0.0
                    ? 0.0
                    : state_.velocity[i].norm() + state_.angular_velocity[i].norm() * (c + a);
    fastest = std::max(fastest, reach_[i]);
  }
  // gravity's speed-up over the step, and a quarter wire radius to spare
  const double slack = 0.25 * a + model_.gravity.norm() * dt * dt;
  const auto margin = [&](int i, int j) { return (reach_[i] + reach_[j]) * dt + slack; };

  order_links();
  std::size_t cursor = 0;

  if (model_.self_contact && n > 1) {
    auto others = profile_.scope(stage_name(TorusXpbdStage::self_contact));
    const double radius = 2.0 * (c + a) + 2.0 * fastest * dt + slack;
    for (int i = 0; i < n; ++i) centres_.col(i) = state_.position[i];
    hash_.build(centres_, radius);
    hash_pairs_.clear();
    hash_.for_each_pair(centres_, radius, [&](int i, int j) {
      const auto& nb = model_.neighbours[i];
      if (nb[0] == j || nb[1] == j || nb[2] == j || nb[3] == j) return;  // linked: above
      if (model_.inverse_mass[i] == 0.0 && model_.inverse_mass[j] == 0.0) return;
      hash_pairs_.push_back({i, j});
    });
    std::sort(hash_pairs_.begin(), hash_pairs_.end(), pair_less);
    previous_pairs_.swap(other_pairs_);
    other_pairs_.clear();
    cursor = 0;
    for (const RingPair& pair : hash_pairs_) {
      const double reach = 2.0 * (c + a) + margin(pair.a, pair.b);
      if ((state_.position[pair.a] - state_.position[pair.b]).squaredNorm() > reach * reach)
        continue;
      carry_pair(pair.a, pair.b, other_pairs_, previous_pairs_, cursor);
    }
  }
  for (auto& others : part_others_) others.clear();
  for (std::size_t k = 0; k < other_pairs_.size(); ++k)
    part_others_[pair_part(other_pairs_[k].a, other_pairs_[k].b)].push_back(static_cast<int>(k));

  for (auto& candidates : part_candidates_) candidates.clear();
  if (model_.colliders.empty()) return;
  auto colliders = profile_.scope(stage_name(TorusXpbdStage::colliders));
  // ring-major like the last step's list, whose deepest angles carry over
  previous_candidates_.swap(collider_candidates_);
  collider_candidates_.clear();
  std::size_t last = 0;
  for (int i = 0; i < n; ++i) {
    if (model_.inverse_mass[i] == 0.0) continue;
    for (int k = 0; k < static_cast<int>(model_.colliders.size()); ++k) {
      const double bound = circle_collider_bound(model_.colliders[k], state_.position[i], c);
      if (bound >= a + reach_[i] * dt + slack) continue;
      ColliderCandidate candidate{i, k};
      while (last < previous_candidates_.size() &&
             (previous_candidates_[last].ring != i ? previous_candidates_[last].ring < i
                                                   : previous_candidates_[last].collider < k))
        ++last;
      if (last < previous_candidates_.size() && previous_candidates_[last].ring == i &&
          previous_candidates_[last].collider == k)
        candidate = previous_candidates_[last];
      part_candidates_[model_.part[i]].push_back(static_cast<int>(collider_candidates_.size()));
      collider_candidates_.push_back(candidate);
    }
  }
}

// breadth-first depth of every ring from the supports (pins, rings that touched a collider in the
// last step), then the links by the depth of their nearer ring: one Gauss-Seidel pass carries the
// supports' push outward through the fabric instead of against it
void TorusXpbdSim::order_links() {
  const int n = static_cast<int>(support_depth_.size());
  mark_near_colliders();
  queue_.clear();
  for (int i = 0; i < n; ++i) {
    const bool support = model_.inverse_mass[i] == 0.0 || touching_[i];
    support_depth_[i] = support ? 0 : -1;
    if (support) queue_.push_back(i);
    touching_[i] = 0;
  }
  for (std::size_t head = 0; head < queue_.size(); ++head) {
    const int ring = queue_[head];
    for (int other : model_.neighbours[ring]) {
      if (other >= 0 && support_depth_[other] < 0) {
        support_depth_[other] = support_depth_[ring] + 1;
        queue_.push_back(other);
      }
    }
  }
  const auto depth = [&](int index) {
    const RingPairContact& pair = link_pairs_[index];
    const int da = support_depth_[pair.a], db = support_depth_[pair.b];
    return da < 0 || db < 0 ? n : std::min(da, db);  // unsupported last
  };
  // a total order (ties by index): std::sort needs no buffer, and the order is deterministic
  std::sort(link_order_.begin(), link_order_.end(),
            [&](int x, int y) { return depth(x) != depth(y) ? depth(x) < depth(y) : x < y; });
  for (auto& links : part_links_) links.clear();
  for (int index : link_order_)
    part_links_[pair_part(link_pairs_[index].a, link_pairs_[index].b)].push_back(index);
}

// the rings within kVelocityReach links of one that touched a collider in the last step (before
// order_links forgets which touched; support_depth_ serves as the breadth-first scratch, which
// order_links then fills anew)
void TorusXpbdSim::mark_near_colliders() {
  const int n = static_cast<int>(near_collider_.size());
  queue_.clear();
  for (int i = 0; i < n; ++i) {
    support_depth_[i] = touching_[i] ? 0 : -1;
    if (touching_[i]) queue_.push_back(i);
  }
  for (std::size_t head = 0; head < queue_.size(); ++head) {
    const int ring = queue_[head];
    if (support_depth_[ring] >= kVelocityReach) continue;
    for (int other : model_.neighbours[ring]) {
      if (other >= 0 && support_depth_[other] < 0) {
        support_depth_[other] = support_depth_[ring] + 1;
        queue_.push_back(other);
      }
    }
  }
  for (int i = 0; i < n; ++i) near_collider_[i] = support_depth_[i] >= 0;
}

void TorusXpbdSim::integrate(double h, int part) {
  for (int i : model_.part_rings[part]) {
    state_.previous_position[i] = state_.position[i];
    state_.previous_orientation[i] = state_.orientation[i];
    previous_rotation_[i] = rotation_[i];
    if (model_.inverse_mass[i] == 0.0 || state_.asleep[i]) continue;
    Vec3& v = state_.velocity[i];
    v += h * model_.gravity;
    state_.position[i] += h * v;
    travel_[i] = (v.norm() + state_.angular_velocity[i].norm() *
                                 (model_.ring.centre_radius + model_.ring.wire_radius)) *
                 h;
    // the gyroscopic torque of a symmetric top, -w x (I w) = (Ia - Id)(axis . w)(axis x w)
    Quat& q = state_.orientation[i];
    Vec3& w = state_.angular_velocity[i];
    const Vec3 axis = rotation_[i].col(1);
    const double spread = model_.inertia_axis[i] - model_.inertia_diameter[i];
    w += h * inverse_inertia_times(i, spread * axis.dot(w) * axis.cross(w));
    const Quat turn = Quat(0.0, w.x(), w.y(), w.z()) * q;
    q.coeffs() += 0.5 * h * turn.coeffs();
    q.normalize();
    rotation_[i] = q.toRotationMatrix();
  }
}

void TorusXpbdSim::update_velocities(double h, int part) {
  const double keep = std::exp(-model_.settings.damping * h);
  const double c = model_.ring.centre_radius;
  for (int i : model_.part_rings[part]) {
    if (model_.inverse_mass[i] == 0.0) continue;
    const Vec3 v = (state_.position[i] - state_.previous_position[i]) / h;
    const Quat turn = state_.orientation[i] * state_.previous_orientation[i].conjugate();
    Vec3 w = (2.0 / h) * turn.vec();
    if (turn.w() < 0.0) w = -w;
    state_.velocity[i] = keep * v;
    state_.angular_velocity[i] = keep * w;
    // a sleeping ring that a contact moved wakes up
    if (state_.asleep[i] && v.norm() + w.norm() * c > kSleepSpeed) {
      state_.asleep[i] = 0;
      state_.still_time[i] = 0.0;
    }
  }
}

void TorusXpbdSim::update_sleep(double dt) {
  const int n = static_cast<int>(state_.position.size());
  const double c = model_.ring.centre_radius;
  for (int i = 0; i < n; ++i) {
    if (model_.inverse_mass[i] == 0.0 || state_.asleep[i]) continue;
    const double speed = state_.velocity[i].norm() + state_.angular_velocity[i].norm() * c;
    state_.still_time[i] = speed < kSleepSpeed ? state_.still_time[i] + dt : 0.0;
    if (state_.still_time[i] >= kSleepDelay) {
      state_.asleep[i] = 1;
      state_.velocity[i].setZero();
      state_.angular_velocity[i].setZero();
    }
  }
}

bool TorusXpbdSim::finite() const {
  for (std::size_t i = 0; i < state_.position.size(); ++i) {
    if (!state_.position[i].allFinite() || !state_.orientation[i].coeffs().allFinite() ||
        !state_.velocity[i].allFinite() || !state_.angular_velocity[i].allFinite())
      return false;
  }
  return true;
}

void TorusXpbdSim::frame(RingFrame& out) const {
  const int n = static_cast<int>(state_.position.size());
  out.t = state_.t;
  out.resize(n);
  for (int i = 0; i < n; ++i) {
    out.position.col(i) = state_.position[i];
    out.set_quat(i, state_.orientation[i]);
    out.velocity.col(i) = state_.velocity[i];
  }
}

double TorusXpbdSim::energy() const {
  double total = 0.0;
  for (std::size_t i = 0; i < state_.position.size(); ++i) {
    if (model_.inverse_mass[i] == 0.0) continue;
    const double m = 1.0 / model_.inverse_mass[i];
    const Vec3& w = state_.angular_velocity[i];
    const double along = w.dot(state_.orientation[i] * Vec3::UnitY());
    const double across2 = w.squaredNorm() - along * along;
    total += 0.5 * m * state_.velocity[i].squaredNorm() -
             m * model_.gravity.dot(state_.position[i]) +
             0.5 * (model_.inertia_axis[i] * along * along + model_.inertia_diameter[i] * across2);
  }
  return total;
}

}  // namespace chainmail
