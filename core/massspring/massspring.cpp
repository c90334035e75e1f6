#include "core/massspring/massspring.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace chainmail::massspring {
namespace {

// dense (i, j) -> mass lookup over the bounding box of weave.grid; -1 where no mass sits
class GridLookup {
 public:
  explicit GridLookup(const Weave& weave) {
    if (weave.size() == 0) return;
    i0_ = j0_ = 1 << 30;
    int i1 = -(1 << 30), j1 = -(1 << 30);
    for (const auto& [i, j] : weave.grid) {
      i0_ = std::min(i0_, i), j0_ = std::min(j0_, j);
      i1 = std::max(i1, i), j1 = std::max(j1, j);
    }
    ni_ = i1 - i0_ + 1, nj_ = j1 - j0_ + 1;
    index_.assign(static_cast<size_t>(ni_) * nj_, -1);
    for (int m = 0; m < weave.size(); ++m) {
      index_[(weave.grid[m][0] - i0_) * static_cast<size_t>(nj_) + (weave.grid[m][1] - j0_)] = m;
    }
  }
  int at(int i, int j) const {
    i -= i0_, j -= j0_;
    if (i < 0 || j < 0 || i >= ni_ || j >= nj_) return -1;
    return index_[i * static_cast<size_t>(nj_) + j];
  }

 private:
  int i0_ = 0, j0_ = 0, ni_ = 0, nj_ = 0;
  std::vector<int> index_;  // (ni * nj)
};

// the unnormalised surface normal and row direction at mass m from its grid neighbours:
// u = p(i+1, j) - p(i-1, j) (one-sided at the border); n = the sum of d(k+1) x d(k) over the
// quadrants whose two edges exist, with d0..d3 the edges to (i+1, j), (i, j+1), (i-1, j), (i, j-1),
// so that a border mass gets a normal that agrees with its inner neighbours; a mass with no
// quadrant (a chain) falls back to v x u, v = p(i, j+1) - p(i, j-1)
void neighbour_vectors(const Positions& position, const Weave& weave, int m, Vec3& u, Vec3& n) {
  const auto& nb = weave.neighbours[m];
  const Vec3 p = position.col(m);
  auto at = [&](int k) { return k >= 0 ? Vec3(position.col(k)) : p; };
  u = at(nb[1]) - at(nb[0]);
  const int around[4] = {nb[1], nb[3], nb[0], nb[2]};  // +i, +j, -i, -j
  n = Vec3::Zero();
  for (int k = 0; k < 4; ++k) {
    const int a = around[k], b = around[(k + 1) % 4];
    if (a >= 0 && b >= 0) n += (at(b) - p).cross(at(a) - p);
  }
  if (n.squaredNorm() == 0.0) n = (at(nb[3]) - at(nb[2])).cross(u);
}

}  // namespace

Vec3 State::velocity(int i) const {
  if (last_dt <= 0.0) return Vec3::Zero();
  return (position.col(i) - previous.col(i)) / last_dt;
}

Vec3 hooke_force(const Vec3& p0, const Vec3& p1, double rest, double ks) {
  const Vec3 d = p1 - p0;
  const double length = d.norm();
  if (length <= 0.0) return Vec3::Zero();  // coincident ends: no direction to push along
  return (ks * (length - rest) / length) * d;
}

std::vector<Spring> build_springs(const Weave& weave, const Positions& rest,
                                  const Settings& settings) {
  const GridLookup lookup(weave);
  std::vector<Spring> springs;
  auto add = [&](int a, int b, double k, SpringKind kind) {
    if (b < 0) return;
    springs.push_back({a, b, (rest.col(b) - rest.col(a)).norm(), k, kind});
  };
  // each pair once: only the "forward" partners of every mass
  for (int m = 0; m < weave.size(); ++m) {
    const auto [i, j] = weave.grid[m];
    add(m, lookup.at(i + 1, j), settings.ks, SpringKind::structural);
    add(m, lookup.at(i, j + 1), settings.ks, SpringKind::structural);
    add(m, lookup.at(i + 1, j + 1), settings.shear_ks, SpringKind::shear);
    add(m, lookup.at(i + 1, j - 1), settings.shear_ks, SpringKind::shear);
    add(m, lookup.at(i + 2, j), settings.bend_ks, SpringKind::bending);
    add(m, lookup.at(i, j + 2), settings.bend_ks, SpringKind::bending);
  }
  return springs;
}

double area_per_mass(const Weave& weave, const Positions& rest) {
  if (weave.size() == 0) return 0.0;
  const GridLookup lookup(weave);
  double area = 0.0;
  // every complete grid cell (i, j) .. (i+1, j+1), as two triangles
  for (int m = 0; m < weave.size(); ++m) {
    const auto [i, j] = weave.grid[m];
    const int a = lookup.at(i + 1, j), b = lookup.at(i + 1, j + 1), c = lookup.at(i, j + 1);
    if (a < 0 || b < 0 || c < 0) continue;
    const Vec3 p = rest.col(m);
    const Vec3 pa = rest.col(a) - p, pb = rest.col(b) - p, pc = rest.col(c) - p;
    area += 0.5 * pa.cross(pb).norm() + 0.5 * pb.cross(pc).norm();
  }
  return area / weave.size();
}

int correct_overextension(const std::vector<Spring>& springs, const Eigen::VectorXd& inv_mass,
                          double max_extension, Positions& position) {
  int over = 0;
  for (const Spring& s : springs) {
    const double w = inv_mass[s.a] + inv_mass[s.b];
    const Vec3 d = position.col(s.b) - position.col(s.a);
    const double length = d.norm();
    const double limit = (1.0 + max_extension) * s.rest;
    if (length <= limit) continue;
    ++over;
    if (w <= 0.0) continue;  // both ends pinned
    // shorten to the limit; the excess is shared by inverse mass (halves for equal masses)
    const Vec3 shift = ((length - limit) / (length * w)) * d;
    position.col(s.a) += inv_mass[s.a] * shift;
    position.col(s.b) -= inv_mass[s.b] * shift;
  }
  return over;
}

double project_out(const Collider& collider, double margin, Vec3& p, Vec3& normal) {
  switch (collider.type) {
    case Collider::Type::plane: {
      const double s = (p - collider.center).dot(collider.normal) - margin;
      if (s >= 0.0) return 0.0;
      normal = collider.normal;
      p -= s * normal;
      return -s;
    }
    case Collider::Type::sphere: {
      const Vec3 d = p - collider.center;
      const double r = collider.radius + margin, dist = d.norm();
      if (dist >= r) return 0.0;
      normal = dist > 0.0 ? Vec3(d / dist) : Vec3::UnitY();
      p = collider.center + r * normal;
      return r - dist;
    }
    case Collider::Type::box: {
      const Vec3 d = p - collider.center;
      const Vec3 h = collider.half_extents.array() + margin;
      const Vec3 room = h.array() - d.array().abs();  // distance to each face pair, inside > 0
      if ((room.array() <= 0.0).any()) return 0.0;
      // leave through the nearest face
      int axis = 0;
      room.minCoeff(&axis);
      normal = Vec3::Zero();
      normal[axis] = d[axis] >= 0.0 ? 1.0 : -1.0;
      p[axis] = collider.center[axis] + normal[axis] * h[axis];
      return room[axis];
    }
    case Collider::Type::cylinder: {
      // solid capped cylinder, axis along world y
      const Vec3 d = p - collider.center;
      const double r = collider.radius + margin, h = collider.half_height + margin;
      const double radial = std::hypot(d.x(), d.z());
      const double side = r - radial, cap = h - std::abs(d.y());
      if (side <= 0.0 || cap <= 0.0) return 0.0;
      if (cap < side) {
        normal = Vec3(0.0, d.y() >= 0.0 ? 1.0 : -1.0, 0.0);
        p.y() = collider.center.y() + normal.y() * h;
        return cap;
      }
      normal = radial > 0.0 ? Vec3(d.x() / radial, 0.0, d.z() / radial) : Vec3::UnitX();
      p.x() = collider.center.x() + r * normal.x();
      p.z() = collider.center.z() + r * normal.z();
      return side;
    }
  }
  return 0.0;
}

void apply_friction(const Vec3& p_prev, const Vec3& normal, double depth, double friction,
                    Vec3& p) {
  const Vec3 motion = p - p_prev;
  const Vec3 tangential = motion - motion.dot(normal) * normal;
  const double slide = tangential.norm();
  const double limit = friction * depth;
  if (slide <= limit) {
    p -= tangential;  // static: stick
  } else {
    p -= (limit / slide) * tangential;  // kinetic: lose friction * depth of the slide
  }
}

std::vector<std::int8_t> normal_signs(const Weave& weave) {
  std::vector<std::int8_t> sign(weave.size(), 1);
  for (int m = 0; m < weave.size(); ++m) {
    Vec3 u, n;
    neighbour_vectors(weave.rest_position, weave, m, u, n);
    sign[m] = n.dot(weave.normal_axis) < 0.0 ? -1 : 1;
  }
  return sign;
}

void surface_orientations(const Positions& position, const Weave& weave,
                          const std::vector<std::int8_t>& flip, Orientations& orientation) {
  const int n = static_cast<int>(position.cols());
  orientation.resize(4, n);
  for (int m = 0; m < n; ++m) {
    Vec3 u, normal;
    neighbour_vectors(position, weave, m, u, normal);
    // a chain or a collapsed patch has no surface: fall back to the rest sheet normal
    Vec3 y = normal.norm() > 1e-12 * std::max(1.0, u.squaredNorm()) ? Vec3(normal.normalized())
                                                                    : weave.normal_axis;
    if (flip[m] < 0) y = -y;
    Vec3 x = u - u.dot(y) * y;
    if (x.norm() < 1e-12) {
      // no row direction either: any unit vector perpendicular to the axis
      x = y.unitOrthogonal();
    }
    x.normalize();
    if (std::abs(x.dot(y)) > 1e-9) y = (y - y.dot(x) * x).normalized();
    Mat3 basis;
    basis.col(0) = x, basis.col(1) = y, basis.col(2) = x.cross(y);
    const Quat q = Quat(basis).normalized();
    orientation.col(m) << q.w(), q.x(), q.y(), q.z();
  }
}

Settings derive_stiffness(const Settings& settings, const Weave& weave, double mass,
                          double gravity) {
  Settings s = settings;
  if (s.ks <= 0.0) {
    const GridLookup lookup(weave);
    const Positions& rest = weave.rest_position;
    double length = 0.0;
    int count = 0;
    for (int m = 0; m < weave.size(); ++m) {
      const auto [i, j] = weave.grid[m];
      for (const int b : {lookup.at(i + 1, j), lookup.at(i, j + 1)}) {
        if (b < 0) continue;
        length += (rest.col(b) - rest.col(m)).norm();
        ++count;
      }
    }
    if (count > 0 && length > 0.0 && s.stretch > 0.0) {
      length /= count;
      const Vec3 extent = rest.rowwise().maxCoeff() - rest.rowwise().minCoeff();
      const double n = 1.0 + extent.maxCoeff() / length;
      const double g = gravity > 0.0 ? gravity : 9.81;
      s.ks = mass * g * n / (2.0 * s.stretch * length);
    }
  }
  if (s.shear_ks <= 0.0) s.shear_ks = kShearFraction * s.ks;
  if (s.bend_ks <= 0.0) s.bend_ks = kBendFraction * s.ks;
  return s;
}

double highest_frequency(const Model& model) {
  Eigen::VectorXd stiffness = Eigen::VectorXd::Zero(model.size());
  for (const Spring& s : model.springs) {
    stiffness[s.a] += s.k;
    stiffness[s.b] += s.k;
  }
  double omega2 = 0.0;
  for (int m = 0; m < model.size(); ++m) {
    omega2 = std::max(omega2, 2.0 * stiffness[m] * model.inv_mass[m]);
  }
  return std::sqrt(omega2);
}

int stable_substeps(const Model& model, double dt) {
  const double steps = std::ceil(highest_frequency(model) * dt / kVerletReach);
  return static_cast<int>(std::clamp(steps, 1.0, 1000.0));
}

Model make_model(const Scene& scene, const Weave& weave, const Settings& given) {
  Model model;
  model.gravity = scene.gravity;
  model.colliders = scene.colliders;

  // mass per point: areal density x rest area per mass, else the given point mass
  const int n = weave.size();
  double m = given.point_mass;
  if (given.areal_density > 0.0)
    m = given.areal_density * area_per_mass(weave, weave.rest_position);
  if (!(m > 0.0) || !std::isfinite(m)) {
    throw std::invalid_argument(
        "massspring: mass per point is not positive (areal density needs a sheet with area)");
  }
  // the scene's loads scale their rings' masses
  const std::vector<double> ring_mass = ring_masses(scene, weave);
  model.mass.resize(n);
  for (int i = 0; i < n; ++i) model.mass[i] = m * (ring_mass[i] / scene.ring.mass());
  model.inv_mass = model.mass.cwiseInverse();
  model.pinned.assign(n, 0);
  for (int ring : resolve_pins(scene, weave)) {
    model.pinned[ring] = 1;
    model.inv_mass[ring] = 0.0;
  }
  model.rigid = rigid_freedom(weave.rest_position, model.inv_mass);
  model.settings = derive_stiffness(given, weave, m, scene.gravity.norm());
  model.springs = build_springs(weave, weave.rest_position, model.settings);
  for (const Spring& s : model.springs) {
    if (model.settings.correct_all || s.kind == SpringKind::structural)
      model.corrected.push_back(s);
  }
  return model;
}

State make_state(const Model& model, const Positions& rest) {
  State state;
  state.position = rest;
  state.previous = rest;
  state.force = Positions::Zero(3, rest.cols());
  return state;
}

void accumulate_forces(const Model& model, const Positions& position, Positions& force) {
  // gravity, then every spring on both of its ends
  for (int m = 0; m < model.size(); ++m) force.col(m) = model.mass[m] * model.gravity;
  for (const Spring& s : model.springs) {
    const Vec3 f = hooke_force(position.col(s.a), position.col(s.b), s.rest, s.k);
    force.col(s.a) += f;
    force.col(s.b) -= f;
  }
}

void verlet_integrate(const Model& model, double dt, State& state) {
  const Settings& settings = model.settings;
  // the percentage applies per document step, whatever the step here
  const double keep = std::pow(std::max(0.0, 1.0 - settings.damping_percent / 100.0),
                               dt / settings.damping_interval);
  const double dt2 = dt * dt;
  // this step's motion so far, m (pinned: none), and the part of it that damping removes
  Positions motion = state.position - state.previous;
  for (int m = 0; m < model.size(); ++m) {
    if (model.pinned[m]) motion.col(m).setZero();
  }
  Positions damped = motion;
  if (!settings.damp_rigid) {
    damp_toward_rigid(model.rigid, state.position, model.mass, model.inv_mass, 1.0, damped);
    damped = motion - damped;  // the deviation from rigid motion
  }
  for (int m = 0; m < model.size(); ++m) {
    if (model.pinned[m]) continue;
    const Vec3 x = state.position.col(m);
    state.position.col(m) = x + motion.col(m) - (1.0 - keep) * damped.col(m) +
                            (model.inv_mass[m] * dt2) * state.force.col(m);
    state.previous.col(m) = x;
  }
  state.last_dt = dt;
}

int constrain(const Model& model, State& state) {
  int over = 0;
  for (int pass = 0; pass < model.settings.correction_passes; ++pass) {
    over = correct_overextension(model.corrected, model.inv_mass, model.settings.max_extension,
                                 state.position);
    if (over == 0) break;  // nothing left to correct
  }
  return over;
}

int collide(const Model& model, State& state) {
  int pushed = 0;
  if (state.contact.size() != static_cast<size_t>(model.size()))
    state.contact.assign(model.size(), 0);
  for (int m = 0; m < model.size(); ++m) {
    if (model.pinned[m]) continue;
    Vec3 p = state.position.col(m);
    bool touched = false;
    for (const Collider& collider : model.colliders) {
      Vec3 normal;
      const double depth = project_out(collider, model.settings.collision_margin, p, normal);
      if (depth <= 0.0) continue;
      apply_friction(state.previous.col(m), normal, depth, collider.friction, p);
      // friction moves along the surface only, but keep the mass outside exactly
      Vec3 again;
      project_out(collider, model.settings.collision_margin, p, again);
      touched = true;
    }
    if (touched) {
      state.position.col(m) = p;
      state.contact[m] = 1;
      ++pushed;
    }
  }
  return pushed;
}

int self_collide(const Model& model, State& state) {
  const double thickness = model.settings.thickness;
  const int n = model.size();
  if (thickness <= 0.0 || n < 2) return 0;

  // candidate pairs: search again when a mass has moved half the skin since the last search, so
  // no pair outside the list can have come closer than the thickness
  const double skin = model.settings.self_collision_skin * thickness;
  bool search = state.searched_at.cols() != n;
  for (int m = 0; !search && m < n; ++m) {
    search = (state.position.col(m) - state.searched_at.col(m)).squaredNorm() > 0.25 * skin * skin;
  }
  if (search) {
    const double reach = thickness + skin;
    state.hash.build(state.position, reach);
    state.candidates.clear();
    state.hash.for_each_pair(state.position, reach, [&](int i, int j) {
      state.candidates.push_back({i, j});
    });
    state.searched_at = state.position;
  }

  // weights: a mass on a collider holds still against a free one
  auto weight = [&](int m, bool other_free) {
    const bool held = m < static_cast<int>(state.contact.size()) && state.contact[m];
    return held && other_free ? 0.0 : model.inv_mass[m];
  };
  auto is_free = [&](int m) {
    return m >= static_cast<int>(state.contact.size()) || !state.contact[m];
  };

  // Gauss-Seidel sweeps: apart to the thickness along the line between them
  int pushed = 0;
  for (int pass = 0; pass < model.settings.self_collision_passes; ++pass) {
    int pushed_this_pass = 0;
    for (const RingPair& pair : state.candidates) {
      const Vec3 d = state.position.col(pair.b) - state.position.col(pair.a);
      const double dist2 = d.squaredNorm();
      if (dist2 >= thickness * thickness) continue;
      const double wa = weight(pair.a, is_free(pair.b)), wb = weight(pair.b, is_free(pair.a));
      if (wa + wb <= 0.0) continue;
      const double dist = std::sqrt(dist2);
      const Vec3 dir = dist > 0.0 ? Vec3(d / dist) : Vec3::UnitY();
      const Vec3 shift = ((thickness - dist) / (wa + wb)) * dir;
      state.position.col(pair.a) -= wa * shift;
      state.position.col(pair.b) += wb * shift;
      ++pushed_this_pass;
    }
    pushed += pushed_this_pass;
    if (pushed_this_pass == 0) break;
  }
  return pushed;
}

bool needs(const Model& model, Stage stage) {
  switch (stage) {
    case Stage::constrain:
      return model.settings.correction_passes > 0 && !model.corrected.empty();
    case Stage::colliders:
      return !model.colliders.empty();
    case Stage::self_contact:
      return model.settings.self_collision;
    default:
      return true;
  }
}

void run_stage(Stage stage, const Model& model, State& state, double dt, StageProfile& profile) {
  if (!needs(model, stage)) return;
  auto scope = profile.scope(stage_name(stage));
  switch (stage) {
    case Stage::forces:
      accumulate_forces(model, state.position, state.force);
      break;
    case Stage::integrate:
      verlet_integrate(model, dt, state);
      break;
    case Stage::constrain:
      constrain(model, state);
      break;
    case Stage::colliders:
      collide(model, state);
      break;
    case Stage::self_contact:
      self_collide(model, state);
      break;
  }
}

void step(const Model& model, State& state, double dt, StageProfile& profile) {
  std::fill(state.contact.begin(), state.contact.end(), 0);  // no mass has touched a collider yet
  for (const Stage stage : {Stage::forces, Stage::integrate, Stage::constrain, Stage::colliders})
    run_stage(stage, model, state, dt, profile);
  // self-collision and colliders in turn, so each one's push is seen by the other
  const int rounds = model.settings.self_collision ? model.settings.contact_rounds : 0;
  for (int round = 0; round < rounds; ++round) {
    for (const Stage stage : {Stage::self_contact, Stage::colliders})
      run_stage(stage, model, state, dt, profile);
  }
  state.t += dt;
}

}  // namespace chainmail::massspring
