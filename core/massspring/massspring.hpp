// Mass-spring cloth (the cloth document): a grid of point masses joined by structural, shear and
// bending Hooke springs, Verlet integration with percent damping, the over-extension correction
// that keeps every spring within (1 + max_extension) of its rest length, pins, collider contact
// with Coulomb friction and self-collision through the spatial hash with a thickness.
//
// The model (springs, masses, pins, colliders, settings) is built once and never changes; the
// state (positions now and one step ago) is all that a step advances. The spring and contact
// functions are stateless so they can be tested one by one.
#pragma once

#include <cstdint>
#include <vector>

#include "core/damping.hpp"
#include "core/profile.hpp"
#include "core/scene.hpp"
#include "core/spatial_hash.hpp"
#include "core/types.hpp"
#include "core/weave.hpp"

namespace chainmail::massspring {

enum class SpringKind : std::uint8_t { structural, shear, bending };

// one Hooke spring between masses a and b
struct Spring {
  int a = 0;
  int b = 0;
  double rest = 0.0;  // m
  double k = 0.0;     // N/m
  SpringKind kind = SpringKind::structural;
};

// the derived stiffnesses (derive_stiffness): shear and bending as fractions of the structural
// constant, soft as a game cloth sets them (chainmail, like cloth, shears almost freely)
inline constexpr double kShearFraction = 0.02;
inline constexpr double kBendFraction = 0.02;
// the substeps derived for a step (stable_substeps) keep omega_max h at most this; Verlet is
// stable below 2, and omega_max is an upper bound
inline constexpr double kVerletReach = 1.0;

struct Settings {
  // spring constants, N/m; 0 = derived from the sheet (derive_stiffness)
  double ks = 0.0;        // structural
  double shear_ks = 0.0;  // 0: kShearFraction ks
  double bend_ks = 0.0;   // 0: kBendFraction ks
  // the derived ks: a column as long as the sheet, hung from its top, stretches this fraction
  // of its length under its own weight
  double stretch = 0.03;
  // d: x_new = x + (x - x_prev) - (1 - keep)(x - x_prev - rigid) + a dt^2, keep = (1 - d/100)
  // per damping_interval; rigid is the step's rigid motion of the whole (damp_rigid: none)
  double damping_percent = 1.0;
  double damping_interval = 1.0 / 2700.0;  // s, the document's step (90 frames/s x 30 steps)
  bool damp_rigid = false;                 // damp all motion, as the document does
  int correction_passes = 1;               // over-extension passes per step (the document uses one)
  double max_extension = 0.1;              // springs are kept within (1 + max_extension) rest
  // the correction holds every spring, as the document does; off: the structural springs only,
  // so that the sheet shears as freely as its soft shear springs let it
  bool correct_all = false;
  bool self_collision = false;       // the self_collide stage runs only when set
  double thickness = 0.0;            // m; no two masses closer than this (self-collision)
  int self_collision_passes = 16;    // most projection sweeps over the candidate pairs per step
  double self_collision_skin = 0.5;  // candidate search reach beyond the thickness, x thickness
  int contact_rounds = 2;            // self_collide + collide rounds per step
  double areal_density = 0.0;        // kg/m^2; 0 = every mass weighs point_mass
  double point_mass = 0.0;           // kg, used when areal_density is 0
  double collision_margin = 0.0;     // m; masses stay this far outside every collider
};

struct Model {
  std::vector<Spring> springs;       // (m)
  std::vector<Spring> corrected;     // the springs the over-extension correction holds
  Eigen::VectorXd mass;              // (n) kg
  Eigen::VectorXd inv_mass;          // (n) 1/kg; 0 for pinned masses
  std::vector<std::uint8_t> pinned;  // (n) 1 = never moves
  std::vector<Collider> colliders;
  Vec3 gravity = Vec3(0.0, -9.81, 0.0);  // m/s^2
  RigidFreedom rigid;                    // rigid motions the pins leave (damping spares them)
  Settings settings;

  int size() const { return static_cast<int>(mass.size()); }
};

struct State {
  Positions position;    // (3, n) m
  Positions previous;    // (3, n) m, position one step earlier (Verlet)
  Positions force;       // (3, n) N, scratch of the force phase
  double t = 0.0;        // s
  double last_dt = 0.0;  // s, the step that produced position from previous

  std::vector<std::uint8_t> contact;  // (n) 1 = pushed out of a collider during this step

  // self-collision scratch: candidate pairs within thickness + skin of the positions at the last
  // search; searched again once any mass has moved more than half the skin since then
  SpatialHash hash;
  std::vector<RingPair> candidates;
  Positions searched_at;  // (3, n) m

  int size() const { return static_cast<int>(position.cols()); }
  Vec3 velocity(int i) const;  // (position - previous) / last_dt, m/s
};

// --- stateless pieces --------------------------------------------------------------------------

// Hooke's law: the force on the mass at p0 of a spring to p1, k (|d| - rest) d / |d|, d = p1 - p0
Vec3 hooke_force(const Vec3& p0, const Vec3& p1, double rest, double ks);

// springs from grid topology: structural (i+-1, j), (i, j+-1); shear the four diagonals; bending
// (i+-2, j), (i, j+-2); rest lengths are the distances in the rest layout
std::vector<Spring> build_springs(const Weave& weave, const Positions& rest,
                                  const Settings& settings);

// rest area of the sheet (sum of the grid cells' quads) divided by the number of masses, m^2
double area_per_mass(const Weave& weave, const Positions& rest);

// one pass of the document's correction: every spring longer than (1 + max_extension) rest is
// shortened to that length by moving its ends (weighted by inverse mass; pinned ends stay).
// Returns how many springs were over-extended when visited.
int correct_overextension(const std::vector<Spring>& springs, const Eigen::VectorXd& inv_mass,
                          double max_extension, Positions& position);

// pushes p out of the collider (plus margin); returns the penetration depth removed (0: none)
// and the outward surface normal in `normal`
double project_out(const Collider& collider, double margin, Vec3& p, Vec3& normal);

// Coulomb friction at position level: the tangential part of this step's motion (p - p_prev)
// is cancelled when it is below friction * depth (sticking) and shortened by that much otherwise
void apply_friction(const Vec3& p_prev, const Vec3& normal, double depth, double friction, Vec3& p);

// ring orientation that follows the cloth surface (no swivel): axis (local +Y) = the surface normal
// from neighbour vectors, local X along (i+1, j) - (i-1, j); `flip` per ring turns the normal
// over so that it agrees with the rest layout's normal. (4, n) w, x, y, z
void surface_orientations(const Positions& position, const Weave& weave,
                          const std::vector<std::int8_t>& flip, Orientations& orientation);
// +1 / -1 per ring: whether the neighbour-vector normal of the rest layout already points along
// weave.normal_axis
std::vector<std::int8_t> normal_signs(const Weave& weave);

// ks = m g n / (2 stretch L): a column of n masses m spaced L, hung from its top, stretches by
// the fraction `stretch` of its length (the spring below mass k carries k m g). L is the mean rest
// length of the structural springs, n = 1 + D / L with D the largest side of the rest layout's
// bounding box, g = |gravity| (9.81 m/s^2 without gravity). Fills ks, then shear_ks and bend_ks,
// where they are 0; the others are returned as given.
Settings derive_stiffness(const Settings& settings, const Weave& weave, double mass,
                          double gravity);

// an upper bound of the springs' highest angular frequency, rad/s: Gershgorin's bound
// max_i 2 sum_(springs at i) k / m_i of the free masses' stiffness matrix at rest
double highest_frequency(const Model& model);
// the fewest Verlet steps per dt that keep highest_frequency(model) h within kVerletReach
int stable_substeps(const Model& model, double dt);

// --- model and step ----------------------------------------------------------------------------

Model make_model(const Scene& scene, const Weave& weave, const Settings& settings);
// at rest in the weave's rest layout, zero velocity
State make_state(const Model& model, const Positions& rest);

// phases of one step, in order
void accumulate_forces(const Model& model, const Positions& position, Positions& force);
void verlet_integrate(const Model& model, double dt, State& state);
int constrain(const Model& model, State& state);  // returns springs corrected, last pass
// pushes masses out of the colliders and marks them in state.contact (step clears the marks)
int collide(const Model& model, State& state);  // returns masses pushed out
// pairs closer than the thickness are pushed apart; a mass resting on a collider (state.contact)
// holds still against a free one. Returns pairs pushed apart.
int self_collide(const Model& model, State& state);

// the stages of a step, as its profile names them (stage_name): forces, integrate, constrain,
// colliders, then rounds of self_contact + colliders (colliders have the last word: self-collision
// may push a free mass into one)
enum class Stage : std::uint8_t { forces, integrate, constrain, colliders, self_contact };
inline const char* stage_name(Stage stage) {
  constexpr const char* kNames[] = {"forces", "integrate", "constrain", "colliders",
                                    "self_contact"};
  return kNames[static_cast<int>(stage)];
}
// whether the model needs the stage at all: one it does not need never runs
bool needs(const Model& model, Stage stage);
// one stage of a step (where the model needs it), timed in the profile under its name
void run_stage(Stage stage, const Model& model, State& state, double dt, StageProfile& profile);

// one time step: its stages in order
void step(const Model& model, State& state, double dt, StageProfile& profile);

}  // namespace chainmail::massspring
