// Scene: one description of one experiment, shared by every backend. Plain structs: scene files
// are read, validated and written by scene_file/scene_file.hpp (see docs/scene-file.md).
#pragma once

#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/ring.hpp"
#include "core/types.hpp"

namespace chainmail {

// bad input: one message naming the file and the key; the command line exits with status 2
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// grid: a plain square grid of point masses (cloth scenes); neighbours share an edge, no rings
// interlock
enum class WeaveType { chain, four_in_one, grid };
// plane of the rest sheet: rows run along the first axis, rows advance along the second
// (xy and yz advance downwards so row 0 is the top; yx runs rows downwards, for hanging chains)
enum class SheetPlane { xz, xy, yz, yx };

struct WeaveSpec {
  WeaveType type = WeaveType::four_in_one;
  int rows = 10;  // physical rows of rings (chain: 1)
  int cols = 10;  // rings per row (chain: number of rings)
  SheetPlane plane = SheetPlane::xz;
  Vec3 center = Vec3::Zero();  // m, centre of the rest sheet
  double spacing = 0.9;  // chain: centre distance / inner diameter; grid: centre distance in m
};

struct PinSpec {
  enum class Kind { ring, edge, corner };
  Kind kind = Kind::ring;
  int row = 0, col = 0;  // kind == ring: physical row and position in the row
  std::string
      which;  // edge: top|bottom|left|right; corner: top_left|top_right|bottom_left|bottom_right
};

struct Collider {
  enum class Type { plane, sphere, box, cylinder };
  Type type = Type::plane;
  Vec3 center = Vec3::Zero();         // m; plane: a point on it
  Vec3 normal = Vec3::UnitY();        // plane only, unit
  Vec3 given_normal = Vec3::UnitY();  // plane: the normal as the scene gave it (any length)
  double radius = 0.0;                // sphere, cylinder; m
  Vec3 half_extents = Vec3::Zero();   // box; m (axis aligned)
  double half_height = 0.0;           // cylinder (axis along world y); m
  double friction = 0.3;              // Coulomb coefficient
};

// the table under a draped sheet, for Cusick's drape coefficient (a disk in the x/z plane)
struct Support {
  Vec3 center = Vec3::Zero();
  double radius = 0.0;
};

struct Camera {
  bool automatic = true;  // frame the fabric when position/target are not given
  Vec3 position = Vec3(0.0, 0.5, 1.0);
  Vec3 target = Vec3::Zero();
  double fov_deg = 40.0;
};

// extra mass on one ring (a weight hanging from the fabric)
struct Load {
  int row = 0, col = 0;
  double mass_factor = 1.0;  // ring mass multiplier
};

struct StabilityBounds {
  double max_speed = 20.0;      // m/s; any ring faster is unstable
  bool links_must_hold = true;  // a torn link (stretched past max_stretch) is an instability
  double max_stretch = 1.25;    // link centre distance / 2(c - a) beyond which a link is torn
  double energy_growth = 1.5;   // total energy may not exceed this factor of its start + input
};

// one knob as the scene file gives it under backends.<backend>.<knob>; its kind and range are
// checked against the backend's knob table by backends/registry
struct KnobValue {
  enum class Kind { number, integer, boolean, string, other };  // other: array, object or null
  Kind kind = Kind::number;
  double value = 0.0;  // booleans 0/1; string, other: 0
  std::string text;    // (string) as given: a choice knob's name
};
// knob name -> value, for one backend
using KnobSection = std::map<std::string, KnobValue>;

struct Scene {
  std::string name;
  std::string description;
  std::string file;  // where it came from, for messages

  RingGeometry ring;
  // m, the inner diameter as the scene gave it (0: not given): 2(c - a) can differ from it in the
  // last bit, and a written scene must read back to the same ring
  double ring_inner_diameter = 0.0;
  double ring_friction = 0.3;  // ring-ring Coulomb coefficient
  WeaveSpec weave;
  std::vector<PinSpec> pins;
  std::vector<Collider> colliders;
  std::optional<Support> support;
  std::vector<Load> loads;
  Vec3 initial_velocity = Vec3::Zero();  // m/s, of every free ring at t = 0
  Vec3 gravity = Vec3(0.0, -9.81, 0.0);  // m/s^2
  double duration = 1.0;                 // s
  double sample_interval = 0.05;         // s between metric samples
  bool self_contact = true;              // non-neighbour ring contact
  bool write_frames = false;             // frames/<backend>/*.csv
  Camera camera;
  StabilityBounds stability;
  std::string reference = "bullet";  // backend whose run drape_rms is measured against
  double reference_dt = 0.0;         // s, the reference run's dt; 0 = that backend's dt here

  std::map<std::string, KnobSection> backends;  // backend name -> its knobs as written
};

// smallest length (m: ring diameters, grid spacing, collider and support sizes) and density
// (kg/m^3) a scene may give: ring mass, inertia and areas stay normal finite doubles
inline constexpr double kMinLength = 1e-6;
inline constexpr double kMinDensity = 1.0;

const char* to_string(WeaveType type);
const char* to_string(SheetPlane plane);
const char* to_string(Collider::Type type);

}  // namespace chainmail
