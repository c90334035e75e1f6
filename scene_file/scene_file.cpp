// Scene files: the reader. Every key is checked against its type and range as written and
// unknown keys are refused, so a scene either loads completely or names the first bad key.
#include "scene_file/scene_file.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/weave.hpp"
#include "scene_file/scene_file_text.hpp"

namespace chainmail {
namespace {

using json = nlohmann::json;

// Reads one JSON object: every key asked for is checked (type, finiteness, range) and its value
// or default returned; finish() refuses the keys nobody asked for.
class Reader {
 public:
  Reader(const json& object, std::string path, const std::string& file)
      : object_(object), path_(std::move(path)), file_(file) {
    if (!object_.is_object()) fail(path_.empty() ? "(top level)" : path_, "must be an object");
  }

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw SceneError(file_ + ": key '" + key + "': " + what);
  }
  std::string key_path(const std::string& key) const {
    return path_.empty() ? key : path_ + "." + key;
  }
  bool has(const std::string& key) const { return object_.contains(key); }

  double number(const std::string& key, std::optional<double> fallback, double min, double max,
                bool min_exclusive = false) {
    const json* value = take(key, fallback.has_value());
    double x = fallback.value_or(0.0);
    if (value) {
      if (!value->is_number()) fail(key_path(key), "must be a number, got " + type_of(*value));
      x = value->get<double>();
    }
    check_range(key, x, min, max, min_exclusive);
    return x;
  }

  int integer(const std::string& key, std::optional<int> fallback, int min, int max) {
    const json* value = take(key, fallback.has_value());
    int x = fallback.value_or(0);
    if (value) {
      if (!value->is_number_integer()) {
        fail(key_path(key), "must be an integer, got " + type_of(*value));
      }
      if (!integer_in(*value, min, max)) {
        fail(key_path(key), "must be in [" + std::to_string(min) + ", " + std::to_string(max) +
                                "], got " + value->dump());  // as written: 2^63 is not negative
      }
      x = value->get<int>();
    }
    return x;
  }

  bool boolean(const std::string& key, bool fallback) {
    const json* value = take(key, true);
    bool x = fallback;
    if (value) {
      if (!value->is_boolean())
        fail(key_path(key), "must be true or false, got " + type_of(*value));
      x = value->get<bool>();
    }
    return x;
  }

  std::string string(const std::string& key, std::optional<std::string> fallback,
                     const std::vector<std::string>& allowed = {}) {
    const json* value = take(key, fallback.has_value());
    std::string x = fallback.value_or("");
    if (value) {
      if (!value->is_string()) fail(key_path(key), "must be a string, got " + type_of(*value));
      x = value->get<std::string>();
    }
    if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), x) == allowed.end()) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      fail(key_path(key), "must be one of " + list + ", got \"" + shown(x) + "\"");
    }
    return x;
  }

  Vec3 vec3(const std::string& key, std::optional<Vec3> fallback, double min = -1e6,
            double max = 1e6) {
    const json* value = take(key, fallback.has_value());
    Vec3 x = fallback.value_or(Vec3::Zero());
    if (value) {
      if (!value->is_array() || value->size() != 3) {
        fail(key_path(key), "must be an array of 3 numbers, got " + type_of(*value));
      }
      for (int k = 0; k < 3; ++k) {
        if (!(*value)[k].is_number()) {
          fail(key_path(key) + "[" + std::to_string(k) + "]",
               "must be a number, got " + type_of((*value)[k]));
        }
        x[k] = (*value)[k].get<double>();
        check_range(key + "[" + std::to_string(k) + "]", x[k], min, max, false);
      }
    }
    return x;
  }

  // a nested object; absent -> nullptr when optional
  const json* child(const std::string& key, bool required) {
    const json* value = take(key, !required);
    if (value && !value->is_object())
      fail(key_path(key), "must be an object, got " + type_of(*value));
    return value;
  }
  // a reader of a nested object; an optional one that is absent reads as empty (all defaults)
  Reader section(const std::string& key, bool required = false) {
    static const json empty = json::object();
    const json* node = child(key, required);
    return Reader(node ? *node : empty, key_path(key), file_);
  }
  const json* array(const std::string& key) {
    const json* value = take(key, true);
    if (value && !value->is_array())
      fail(key_path(key), "must be an array, got " + type_of(*value));
    return value;
  }
  // [row, col] of a ring of a rows x cols weave; `expected` describes the form. Values that do
  // not name a ring are reported as written (not wrapped to int)
  std::array<int, 2> ring_cell(const std::string& key, const std::string& expected, int rows,
                               int cols) {
    const json* ring = array(key);
    if (!ring || ring->size() != 2 || !(*ring)[0].is_number_integer() ||
        !(*ring)[1].is_number_integer()) {
      fail(key_path(key), expected);
    }
    const json &row = (*ring)[0], &col = (*ring)[1];
    if (!integer_in(row, 0, rows - 1) || !integer_in(col, 0, cols - 1)) {
      fail(key_path(key), "ring (row " + row.dump() + ", col " + col.dump() +
                              ") does not exist in a " + std::to_string(rows) + "x" +
                              std::to_string(cols) + " weave");
    }
    return {row.get<int>(), col.get<int>()};
  }
  void finish() const {
    for (auto it = object_.begin(); it != object_.end(); ++it) {
      if (!taken_.count(it.key())) fail(key_path(shown(it.key())), "unknown key");
    }
  }

 private:
  const json* take(const std::string& key, bool optional) {
    taken_.insert(key);
    auto it = object_.find(key);
    if (it == object_.end()) {
      if (!optional) fail(key_path(key), "missing (required)");
      return nullptr;
    }
    return &*it;
  }
  void check_range(const std::string& key, double x, double min, double max,
                   bool min_exclusive) const {
    if (!std::isfinite(x)) fail(key_path(key), "must be finite");
    if ((min_exclusive ? x <= min : x < min) || x > max) {
      // exact numbers: "[1, 1], got 1" hid 1.0000001 > 1 behind 6 digits
      fail(key_path(key), std::string("must be in ") + (min_exclusive ? "(" : "[") +
                              show_number(min) + ", " + show_number(max) + "], got " +
                              show_number(x));
    }
  }
  static std::string type_of(const json& value) { return value.type_name(); }

  const json& object_;
  std::string path_;
  const std::string& file_;
  std::set<std::string> taken_;
};

WeaveType parse_weave_type(const std::string& s) {
  return s == "chain" ? WeaveType::chain : s == "grid" ? WeaveType::grid : WeaveType::four_in_one;
}
SheetPlane parse_plane(const std::string& s) {
  return s == "xy"   ? SheetPlane::xy
         : s == "yz" ? SheetPlane::yz
         : s == "yx" ? SheetPlane::yx
                     : SheetPlane::xz;
}

void read_ring(Scene& scene, Reader& top) {
  Reader r = top.section("ring");
  // lower bounds keep mass (density 2 pi^2 c a^2) and inertia normal doubles
  const double wd = r.number("wire_diameter", 0.0016, kMinLength, 1.0);
  const double id = r.number("inner_diameter", 0.008, kMinLength, 10.0);
  const double density = r.number("density", 7850.0, kMinDensity, 1e5);
  scene.ring_friction = r.number("friction", 0.3, 0.0, 10.0);
  r.finish();
  scene.ring = RingGeometry::from_diameters(wd, id, density);
  scene.ring_inner_diameter = id;
}

// a weave of rings must interlock: checked before its size and spacing, whose ranges follow
// from the aspect ratio (a chain just below AR 2 has no valid spacing at all)
void check_interlock(const Scene& scene) {
  const WeaveType type = scene.weave.type;
  if (type == WeaveType::grid) return;  // point masses: nothing interlocks
  const double min_ar = type == WeaveType::chain ? kChainMinAspectRatio : kFourInOneMinAspectRatio;
  if (scene.ring.aspect_ratio() >= min_ar) return;
  throw SceneError(scene.file + ": key 'ring.inner_diameter': aspect ratio ID/WD = " +
                   show_number(scene.ring.aspect_ratio()) + " is too small for the " +
                   to_string(type) + " weave to interlock (needs ID/WD >= " + show_number(min_ar) +
                   ", so inner_diameter >= " + show_number(min_ar * scene.ring.wire_diameter()) +
                   " for this wire_diameter)");
}

void read_weave(Scene& scene, Reader& top) {
  Reader r = top.section("weave", /*required=*/true);
  WeaveSpec& w = scene.weave;
  w.type = parse_weave_type(r.string("type", std::nullopt, {"chain", "4in1", "grid"}));
  check_interlock(scene);
  if (w.type == WeaveType::chain) {
    w.rows = r.integer("rows", 1, 1, std::numeric_limits<int>::max());
    if (w.rows != 1) {
      r.fail(r.key_path("rows"), "a chain has one row (its length is weave.cols): leave rows out");
    }
    w.cols = r.integer("cols", std::nullopt, 2, 1 << 20);
  } else {
    w.rows = r.integer("rows", std::nullopt, 1, 4096);
    w.cols = r.integer("cols", std::nullopt, 1, 4096);
  }
  w.plane = parse_plane(r.string("plane", "xz", {"xz", "xy", "yz", "yx"}));
  w.center = r.vec3("center", Vec3::Zero());
  if (w.type == WeaveType::chain) {
    // non-neighbours of a chain (k, k+2) share a plane: they must sit at least c + a apart. That
    // is 1/AR + 1/2 inner diameters, at most 1 once AR >= 2 (capped against round-off)
    const double min_spacing = std::min(
        1.0, (scene.ring.centre_radius + scene.ring.wire_radius) / scene.ring.inner_diameter());
    w.spacing = r.number("spacing", std::max(0.9, min_spacing), min_spacing, 1.0);
  } else if (w.type == WeaveType::grid) {
    w.spacing = r.number("spacing", std::nullopt, kMinLength, 100.0);
  } else if (r.has("spacing")) {
    r.fail("weave.spacing", "only a chain takes a spacing (4in1 uses its fixed rest layout)");
  }
  r.finish();
}

void read_pins(Scene& scene, Reader& top) {
  const json* pins = top.array("pins");
  if (!pins) return;
  const int rows = scene.weave.type == WeaveType::chain ? 1 : scene.weave.rows;
  const int cols = scene.weave.cols;
  for (size_t p = 0; p < pins->size(); ++p) {
    Reader r((*pins)[p], "pins[" + std::to_string(p) + "]", scene.file);
    PinSpec pin;
    const int kinds = r.has("ring") + r.has("edge") + r.has("corner");
    if (kinds != 1) r.fail(r.key_path("ring"), "a pin names exactly one of ring, edge, corner");
    if (r.has("ring") && (*pins)[p]["ring"].is_number_integer()) {
      // a ring by its index in the weave (row-major: row * cols + col)
      pin.kind = PinSpec::Kind::ring;
      const int index = r.integer("ring", std::nullopt, 0, rows * cols - 1);
      pin.row = index / cols;
      pin.col = index % cols;
    } else if (r.has("ring")) {
      pin.kind = PinSpec::Kind::ring;
      const auto [row, col] =
          r.ring_cell("ring", "must be a ring index or [row, col] integers", rows, cols);
      pin.row = row;
      pin.col = col;
    } else if (r.has("edge")) {
      pin.kind = PinSpec::Kind::edge;
      pin.which = r.string("edge", std::nullopt, {"top", "bottom", "left", "right"});
    } else {
      pin.kind = PinSpec::Kind::corner;
      pin.which = r.string("corner", std::nullopt,
                           {"top_left", "top_right", "bottom_left", "bottom_right"});
    }
    r.finish();
    scene.pins.push_back(pin);
  }
}

void read_colliders(Scene& scene, Reader& top) {
  const json* colliders = top.array("colliders");
  if (!colliders) return;
  for (size_t k = 0; k < colliders->size(); ++k) {
    Reader r((*colliders)[k], "colliders[" + std::to_string(k) + "]", scene.file);
    Collider c;
    const std::string type = r.string("type", std::nullopt, {"plane", "sphere", "box", "cylinder"});
    c.friction = r.number("friction", 0.3, 0.0, 10.0);
    if (type == "plane") {
      c.type = Collider::Type::plane;
      c.center = r.vec3("point", Vec3::Zero());
      c.given_normal = r.vec3("normal", Vec3::UnitY());
      if (c.given_normal.norm() < 1e-12) {
        r.fail(r.key_path("normal"), "must not be the zero vector");
      }
      c.normal = c.given_normal.normalized();
    } else if (type == "sphere") {
      c.type = Collider::Type::sphere;
      c.center = r.vec3("center", std::nullopt);
      c.radius = r.number("radius", std::nullopt, kMinLength, 1e3);
    } else if (type == "box") {
      c.type = Collider::Type::box;
      c.center = r.vec3("center", std::nullopt);
      c.half_extents = r.vec3("half_extents", std::nullopt, kMinLength, 1e3);
    } else {
      c.type = Collider::Type::cylinder;
      c.center = r.vec3("center", std::nullopt);
      c.radius = r.number("radius", std::nullopt, kMinLength, 1e3);
      c.half_height = r.number("half_height", std::nullopt, kMinLength, 1e3);
    }
    r.finish();
    scene.colliders.push_back(c);
  }
}

void read_support_and_loads(Scene& scene, Reader& top) {
  if (const json* support = top.child("support", false)) {
    Reader r(*support, "support", scene.file);
    Support s;
    s.center = r.vec3("center", std::nullopt);
    s.radius = r.number("radius", std::nullopt, kMinLength, 1e3);
    r.finish();
    scene.support = s;
  }
  const json* loads = top.array("loads");
  if (!loads) return;
  const int rows = scene.weave.type == WeaveType::chain ? 1 : scene.weave.rows;
  for (size_t k = 0; k < loads->size(); ++k) {
    Reader r((*loads)[k], "loads[" + std::to_string(k) + "]", scene.file);
    Load load;
    const auto [row, col] =
        r.ring_cell("ring", "must be [row, col] integers", rows, scene.weave.cols);
    load.row = row;
    load.col = col;
    load.mass_factor = r.number("mass_factor", std::nullopt, 1e-3, 1e6);
    r.finish();
    scene.loads.push_back(load);
  }
}

// backends.<name>.<knob>: objects of knobs whose kinds and ranges backends/registry checks
void read_backend_sections(Scene& scene, const json& backends) {
  if (!backends.is_object()) {
    throw SceneError(scene.file + ": key 'backends': must be an object");
  }
  for (auto it = backends.begin(); it != backends.end(); ++it) {
    if (!it->is_object()) {
      throw SceneError(scene.file + ": key 'backends." + shown(it.key()) + "': must be an object");
    }
    KnobSection& section = scene.backends[it.key()];
    for (auto knob = it->begin(); knob != it->end(); ++knob) {
      KnobValue& v = section[knob.key()];
      if (knob->is_boolean()) {
        v = {KnobValue::Kind::boolean, knob->get<bool>() ? 1.0 : 0.0, {}};
      } else if (knob->is_number_integer()) {
        v = {KnobValue::Kind::integer, knob->get<double>(), {}};  // beyond 2^53: rounded
      } else if (knob->is_number()) {
        v = {KnobValue::Kind::number, knob->get<double>(), {}};
      } else if (knob->is_string()) {
        v = {KnobValue::Kind::string, 0.0, knob->get<std::string>()};
      } else {
        v = {KnobValue::Kind::other, 0.0, {}};
      }
    }
  }
}

// the small optional sections: features, output, camera, stability
void read_settings(Scene& scene, Reader& top) {
  {
    Reader r = top.section("features");
    scene.self_contact = r.boolean("self_contact", true);
    r.finish();
  }
  {
    Reader r = top.section("output");
    scene.write_frames = r.boolean("frames", false);
    r.finish();
  }
  {
    Reader r = top.section("camera");
    scene.camera.automatic = !(r.has("position") || r.has("target"));
    scene.camera.position = r.vec3("position", Vec3(0.0, 0.5, 1.0));
    scene.camera.target = r.vec3("target", Vec3::Zero());
    scene.camera.fov_deg = r.number("fov_deg", 40.0, 1.0, 170.0);
    r.finish();
  }
  Reader r = top.section("stability");
  scene.stability.max_speed = r.number("max_speed", 20.0, 0.0, 1e6, true);
  scene.stability.links_must_hold = r.boolean("links_must_hold", true);
  scene.stability.max_stretch = r.number("max_stretch", 1.25, 1.0, 1e3);
  scene.stability.energy_growth = r.number("energy_growth", 1.5, 1.0, 1e6);
  r.finish();
}

}  // namespace

Scene scene_from_json(const json& document, const std::string& file) {
  // a document built in code skips the parser's depth limit; copies below recurse
  if (nesting_depth(document) > kMaxJsonDepth) {
    throw SceneError(file + ": key '(top level)': nested deeper than " +
                     std::to_string(kMaxJsonDepth) + " levels");
  }
  Scene scene;
  scene.file = file;
  Reader top(document, "", file);

  scene.name = top.string("name", std::nullopt);
  if (scene.name.empty() || scene.name.find_first_of("/\\ .") != std::string::npos) {
    top.fail("name", "must be a non-empty name without spaces, dots or slashes");
  }
  scene.description = top.string("description", "");
  top.string("$schema", "");  // the scene schema, for editors (docs/scene.schema.json): ignored
  read_ring(scene, top);
  read_weave(scene, top);
  read_pins(scene, top);
  read_colliders(scene, top);
  read_support_and_loads(scene, top);
  scene.initial_velocity = top.vec3("initial_velocity", Vec3::Zero(), -1e3, 1e3);
  scene.gravity = top.vec3("gravity", Vec3(0.0, -9.81, 0.0), -1e4, 1e4);
  scene.duration = top.number("duration", std::nullopt, 0.0, 1e5, true);
  scene.sample_interval = top.number("sample_interval", 0.05, 0.0, 1e5, true);
  read_settings(scene, top);
  scene.reference = top.string("reference", "bullet");
  scene.reference_dt = top.number("reference_dt", 0.0, 0.0, 1.0);
  if (const json* backends = top.child("backends", false)) {
    read_backend_sections(scene, *backends);
  }
  top.finish();

  // every pin must name a ring of this weave (only the shape of the weave is needed)
  Weave shape;
  shape.rows = scene.weave.type == WeaveType::chain ? 1 : scene.weave.rows;
  shape.cols = scene.weave.cols;
  resolve_pins(scene, shape);
  return scene;
}

Scene load_scene_file(const std::string& path, const std::vector<std::string>& overrides) {
  json document = parse_json_strict(read_scene_text(path), path);
  for (const auto& assignment : overrides) apply_override(document, assignment, path);
  return scene_from_json(document, path);
}

}  // namespace chainmail
