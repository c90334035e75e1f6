// Scene: one description of one experiment, shared by every backend.
// Loaded from JSON, validated completely before anything runs (see docs/scene-file.md).
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

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
  Vec3 center = Vec3::Zero();        // m; plane: a point on it
  Vec3 normal = Vec3::UnitY();       // plane only, unit
  double radius = 0.0;               // sphere, cylinder; m
  Vec3 half_extents = Vec3::Zero();  // box; m (axis aligned)
  double half_height = 0.0;          // cylinder (axis along world y); m
  double friction = 0.3;             // Coulomb coefficient
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

struct Scene {
  std::string name;
  std::string description;
  std::string file;  // where it came from, for messages

  RingGeometry ring;
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

  nlohmann::json backends = nlohmann::json::object();  // per-backend knobs, validated by backends/
  nlohmann::json resolved;                             // the whole scene with defaults filled in
};

// limits on scene text (docs/scene-file.md). Nesting deeper than kMaxJsonDepth containers
// is refused while parsing, before anything recursive (copy, dump, compare) could overflow the
// stack; a file larger than kMaxSceneFileBytes is refused without reading it all
inline constexpr int kMaxJsonDepth = 64;
inline constexpr long long kMaxSceneFileBytes = 16LL << 20;  // 16 MiB
// smallest length (m: ring diameters, grid spacing, collider and support sizes) and density
// (kg/m^3) a scene may give: ring mass, inertia and areas stay normal finite doubles
inline constexpr double kMinLength = 1e-6;
inline constexpr double kMinDensity = 1.0;

// strict JSON for scene text, comments allowed: refuses duplicate keys, numbers beyond double
// range and nesting deeper than kMaxJsonDepth. Throws SceneError "<source>: key '<path>': <what>"
// or "<source>: JSON syntax error at line L, column C: ..."; never a nlohmann exception
nlohmann::json parse_json_strict(const std::string& text, const std::string& source);

// parse + validate; throws SceneError naming file and key
Scene load_scene_file(const std::string& path, const std::vector<std::string>& overrides = {});
Scene scene_from_json(const nlohmann::json& document, const std::string& file);
// apply one "dotted.key=value" override to a raw scene document; throws SceneError. The value is
// strict JSON when it parses as JSON (1e400 and duplicate keys are errors), else a plain string
void apply_override(nlohmann::json& document, const std::string& assignment,
                    const std::string& file);

const char* to_string(WeaveType type);
const char* to_string(Collider::Type type);

}  // namespace chainmail
