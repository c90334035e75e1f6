#include "core/scene.hpp"

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "core/weave.hpp"

namespace chainmail {
namespace {

using json = nlohmann::json;

// Reads one JSON object: every key asked for is checked (type, finiteness, range) and recorded
// with its resolved value; finish() refuses the keys nobody asked for.
class Reader {
 public:
  Reader(const json& object, std::string path, const std::string& file, json& resolved)
      : object_(object), path_(std::move(path)), file_(file), resolved_(resolved) {
    if (!object_.is_object()) fail(path_.empty() ? "(top level)" : path_, "must be an object");
    resolved_ = json::object();
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
    resolved_[key] = x;
    return x;
  }

  int integer(const std::string& key, std::optional<int> fallback, int min, int max) {
    const json* value = take(key, fallback.has_value());
    int x = fallback.value_or(0);
    if (value) {
      if (!value->is_number_integer()) {
        fail(key_path(key), "must be an integer, got " + type_of(*value));
      }
      const long long wide = value->get<long long>();
      if (wide < min || wide > max) {
        fail(key_path(key), "must be in [" + std::to_string(min) + ", " + std::to_string(max) +
                                "], got " + std::to_string(wide));
      }
      x = static_cast<int>(wide);
    }
    resolved_[key] = x;
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
    resolved_[key] = x;
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
      fail(key_path(key), "must be one of " + list + ", got \"" + x + "\"");
    }
    resolved_[key] = x;
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
    resolved_[key] = {x.x(), x.y(), x.z()};
    return x;
  }

  // a nested object; absent -> empty object when optional
  const json* child(const std::string& key, bool required) {
    const json* value = take(key, !required);
    if (value && !value->is_object())
      fail(key_path(key), "must be an object, got " + type_of(*value));
    return value;
  }
  const json* array(const std::string& key) {
    const json* value = take(key, true);
    if (value && !value->is_array())
      fail(key_path(key), "must be an array, got " + type_of(*value));
    return value;
  }
  json& resolved() { return resolved_; }

  void finish() const {
    for (auto it = object_.begin(); it != object_.end(); ++it) {
      if (!taken_.count(it.key())) fail(key_path(it.key()), "unknown key");
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
    std::ostringstream range;
    range << (min_exclusive ? "(" : "[") << min << ", " << max << "]";
    if ((min_exclusive ? x <= min : x < min) || x > max) {
      std::ostringstream got;
      got << x;
      fail(key_path(key), "must be in " + range.str() + ", got " + got.str());
    }
  }
  static std::string type_of(const json& value) { return value.type_name(); }

  const json& object_;
  std::string path_;
  const std::string& file_;
  json& resolved_;
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
  json& out = top.resolved()["ring"];
  const json* node = top.child("ring", false);
  const json empty = json::object();
  Reader r(node ? *node : empty, "ring", scene.file, out);
  const double wd = r.number("wire_diameter", 0.0016, 0.0, 1.0, true);
  const double id = r.number("inner_diameter", 0.008, 0.0, 10.0, true);
  const double density = r.number("density", 7850.0, 0.0, 1e5, true);
  scene.ring_friction = r.number("friction", 0.3, 0.0, 10.0);
  r.finish();
  scene.ring = RingGeometry::from_diameters(wd, id, density);
}

void read_weave(Scene& scene, Reader& top) {
  json& out = top.resolved()["weave"];
  const json* node = top.child("weave", true);
  Reader r(*node, "weave", scene.file, out);
  WeaveSpec& w = scene.weave;
  w.type = parse_weave_type(r.string("type", std::nullopt, {"chain", "4in1", "grid"}));
  if (w.type == WeaveType::chain) {
    w.rows = r.integer("rows", 1, 1, 1);
    w.cols = r.integer("cols", std::nullopt, 2, 1 << 20);
  } else {
    w.rows = r.integer("rows", std::nullopt, 1, 4096);
    w.cols = r.integer("cols", std::nullopt, 1, 4096);
  }
  w.plane = parse_plane(r.string("plane", "xz", {"xz", "xy", "yz", "yx"}));
  w.center = r.vec3("center", Vec3::Zero());
  if (w.type == WeaveType::chain) {
    // non-neighbours of a chain (k, k+2) share a plane: they must sit at least c + a apart
    const double min_spacing =
        (scene.ring.centre_radius + scene.ring.wire_radius) / scene.ring.inner_diameter();
    w.spacing = r.number("spacing", std::max(0.9, min_spacing), min_spacing, 1.0);
  } else if (w.type == WeaveType::grid) {
    w.spacing = r.number("spacing", std::nullopt, 0.0, 100.0, true);
  } else if (r.has("spacing")) {
    r.fail("weave.spacing", "only a chain takes a spacing (4in1 uses its fixed rest layout)");
  }
  r.finish();
  if (w.type == WeaveType::grid) return;  // point masses: nothing interlocks
  const double min_ar =
      w.type == WeaveType::chain ? kChainMinAspectRatio : kFourInOneMinAspectRatio;
  if (scene.ring.aspect_ratio() < min_ar) {
    std::ostringstream msg;
    msg << "aspect ratio ID/WD = " << scene.ring.aspect_ratio() << " is too small for the "
        << (w.type == WeaveType::chain ? "chain" : "4in1")
        << " weave to interlock (needs >= " << min_ar << ")";
    throw SceneError(scene.file + ": key 'ring.inner_diameter': " + msg.str());
  }
}

void read_pins(Scene& scene, Reader& top) {
  const json* pins = top.array("pins");
  json& out = top.resolved()["pins"] = json::array();
  if (!pins) return;
  for (size_t p = 0; p < pins->size(); ++p) {
    json resolved;
    Reader r((*pins)[p], "pins[" + std::to_string(p) + "]", scene.file, resolved);
    PinSpec pin;
    const int kinds = r.has("ring") + r.has("edge") + r.has("corner");
    if (kinds != 1) r.fail(r.key_path("ring"), "a pin names exactly one of ring, edge, corner");
    if (r.has("ring") && (*pins)[p]["ring"].is_number_integer()) {
      // a ring by its index in the weave (row-major: row * cols + col)
      pin.kind = PinSpec::Kind::ring;
      const int rows = scene.weave.type == WeaveType::chain ? 1 : scene.weave.rows;
      const int index = r.integer("ring", std::nullopt, 0, rows * scene.weave.cols - 1);
      pin.row = index / scene.weave.cols;
      pin.col = index % scene.weave.cols;
      resolved["ring"] = {pin.row, pin.col};
    } else if (r.has("ring")) {
      pin.kind = PinSpec::Kind::ring;
      const json* ring = r.array("ring");
      if (ring->size() != 2 || !(*ring)[0].is_number_integer() || !(*ring)[1].is_number_integer()) {
        r.fail(r.key_path("ring"), "must be a ring index or [row, col] integers");
      }
      pin.row = (*ring)[0].get<int>();
      pin.col = (*ring)[1].get<int>();
      resolved["ring"] = {pin.row, pin.col};
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
    out.push_back(resolved);
  }
}

void read_colliders(Scene& scene, Reader& top) {
  const json* colliders = top.array("colliders");
  json& out = top.resolved()["colliders"] = json::array();
  if (!colliders) return;
  for (size_t k = 0; k < colliders->size(); ++k) {
    json resolved;
    Reader r((*colliders)[k], "colliders[" + std::to_string(k) + "]", scene.file, resolved);
    Collider c;
    const std::string type = r.string("type", std::nullopt, {"plane", "sphere", "box", "cylinder"});
    c.friction = r.number("friction", 0.3, 0.0, 10.0);
    if (type == "plane") {
      c.type = Collider::Type::plane;
      c.center = r.vec3("point", Vec3::Zero());
      c.normal = r.vec3("normal", Vec3::UnitY());
      if (c.normal.norm() < 1e-12) r.fail(r.key_path("normal"), "must not be the zero vector");
      c.normal.normalize();
    } else if (type == "sphere") {
      c.type = Collider::Type::sphere;
      c.center = r.vec3("center", std::nullopt);
      c.radius = r.number("radius", std::nullopt, 0.0, 1e3, true);
    } else if (type == "box") {
      c.type = Collider::Type::box;
      c.center = r.vec3("center", std::nullopt);
      c.half_extents = r.vec3("half_extents", std::nullopt, 1e-9, 1e3);
    } else {
      c.type = Collider::Type::cylinder;
      c.center = r.vec3("center", std::nullopt);
      c.radius = r.number("radius", std::nullopt, 0.0, 1e3, true);
      c.half_height = r.number("half_height", std::nullopt, 0.0, 1e3, true);
    }
    r.finish();
    scene.colliders.push_back(c);
    out.push_back(resolved);
  }
}

}  // namespace

const char* to_string(WeaveType type) {
  switch (type) {
    case WeaveType::chain:
      return "chain";
    case WeaveType::four_in_one:
      return "4in1";
    case WeaveType::grid:
      return "grid";
  }
  return "?";
}

const char* to_string(Collider::Type type) {
  switch (type) {
    case Collider::Type::plane:
      return "plane";
    case Collider::Type::sphere:
      return "sphere";
    case Collider::Type::box:
      return "box";
    case Collider::Type::cylinder:
      return "cylinder";
  }
  return "?";
}

Scene scene_from_json(const json& document, const std::string& file) {
  Scene scene;
  scene.file = file;
  json resolved;
  Reader top(document, "", file, resolved);

  scene.name = top.string("name", std::nullopt);
  if (scene.name.empty() || scene.name.find_first_of("/\\ .") != std::string::npos) {
    top.fail("name", "must be a non-empty name without spaces, dots or slashes");
  }
  scene.description = top.string("description", "");
  read_ring(scene, top);
  read_weave(scene, top);
  read_pins(scene, top);
  read_colliders(scene, top);

  if (const json* support = top.child("support", false)) {
    Reader r(*support, "support", file, resolved["support"]);
    Support s;
    s.center = r.vec3("center", std::nullopt);
    s.radius = r.number("radius", std::nullopt, 0.0, 1e3, true);
    r.finish();
    scene.support = s;
  }

  if (const json* loads = top.array("loads")) {
    json& out = resolved["loads"] = json::array();
    for (size_t k = 0; k < loads->size(); ++k) {
      json entry;
      Reader r((*loads)[k], "loads[" + std::to_string(k) + "]", file, entry);
      Load load;
      const json* ring = r.array("ring");
      if (!ring || ring->size() != 2 || !(*ring)[0].is_number_integer() ||
          !(*ring)[1].is_number_integer()) {
        r.fail(r.key_path("ring"), "must be [row, col] integers");
      }
      load.row = (*ring)[0].get<int>();
      load.col = (*ring)[1].get<int>();
      entry["ring"] = {load.row, load.col};
      load.mass_factor = r.number("mass_factor", std::nullopt, 1e-3, 1e6);
      r.finish();
      scene.loads.push_back(load);
      out.push_back(entry);
    }
  }
  scene.initial_velocity = top.vec3("initial_velocity", Vec3::Zero(), -1e3, 1e3);
  scene.gravity = top.vec3("gravity", Vec3(0.0, -9.81, 0.0), -1e4, 1e4);
  scene.duration = top.number("duration", std::nullopt, 0.0, 1e5, true);
  scene.sample_interval = top.number("sample_interval", 0.05, 0.0, 1e5, true);

  {
    const json* node = top.child("features", false);
    const json empty = json::object();
    Reader r(node ? *node : empty, "features", file, resolved["features"]);
    scene.self_contact = r.boolean("self_contact", true);
    r.finish();
  }
  {
    const json* node = top.child("output", false);
    const json empty = json::object();
    Reader r(node ? *node : empty, "output", file, resolved["output"]);
    scene.write_frames = r.boolean("frames", false);
    r.finish();
  }
  {
    const json* node = top.child("camera", false);
    const json empty = json::object();
    Reader r(node ? *node : empty, "camera", file, resolved["camera"]);
    scene.camera.automatic = !(r.has("position") || r.has("target"));
    scene.camera.position = r.vec3("position", Vec3(0.0, 0.5, 1.0));
    scene.camera.target = r.vec3("target", Vec3::Zero());
    scene.camera.fov_deg = r.number("fov_deg", 40.0, 1.0, 170.0);
    if (scene.camera.automatic) {
      // keep the resolved scene reloadable with the same meaning: no fixed camera
      r.resolved().erase("position");
      r.resolved().erase("target");
    }
    r.finish();
  }
  {
    const json* node = top.child("stability", false);
    const json empty = json::object();
    Reader r(node ? *node : empty, "stability", file, resolved["stability"]);
    scene.stability.max_speed = r.number("max_speed", 20.0, 0.0, 1e6, true);
    scene.stability.links_must_hold = r.boolean("links_must_hold", true);
    scene.stability.max_stretch = r.number("max_stretch", 1.25, 1.0, 1e3);
    scene.stability.energy_growth = r.number("energy_growth", 1.5, 1.0, 1e6);
    r.finish();
  }
  scene.reference = top.string("reference", "bullet");
  scene.reference_dt = top.number("reference_dt", 0.0, 0.0, 1.0);
  if (const json* backends = top.child("backends", false)) {
    scene.backends = *backends;
  }
  resolved["backends"] = scene.backends;
  top.finish();

  // every pin must name a ring of this weave (only the shape of the weave is needed)
  Weave shape;
  shape.rows = scene.weave.type == WeaveType::chain ? 1 : scene.weave.rows;
  shape.cols = scene.weave.cols;
  resolve_pins(scene, shape);
  for (size_t k = 0; k < scene.loads.size(); ++k) {
    if (shape.ring_at_row_col(scene.loads[k].row, scene.loads[k].col) < 0) {
      throw SceneError(file + ": key 'loads[" + std::to_string(k) + "].ring': ring does not exist");
    }
  }
  scene.resolved = resolved;
  return scene;
}

void apply_override(json& document, const std::string& assignment, const std::string& file) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw SceneError(file + ": --set '" + assignment + "': expected KEY=VALUE");
  }
  const std::string key = assignment.substr(0, eq);
  const std::string text = assignment.substr(eq + 1);
  // the value is JSON when it parses as JSON (numbers, true, [1,2,3]), else a plain string
  json value = json::parse(text, nullptr, false);
  if (value.is_discarded()) value = text;

  json* node = &document;
  std::stringstream parts(key);
  std::string part, walked;
  std::vector<std::string> path;
  while (std::getline(parts, part, '.')) path.push_back(part);
  for (size_t k = 0; k < path.size(); ++k) {
    const std::string& name = path[k];
    walked += (walked.empty() ? "" : ".") + name;
    if (name.empty()) throw SceneError(file + ": --set key '" + key + "': empty path element");
    if (node->is_array()) {
      size_t index = 0;
      try {
        index = std::stoul(name);
      } catch (const std::exception&) {
        throw SceneError(file + ": --set key '" + walked + "': expected an array index");
      }
      if (index >= node->size()) {
        throw SceneError(file + ": --set key '" + walked + "': index out of range");
      }
      node = &(*node)[index];
    } else {
      if (!node->is_object()) {
        throw SceneError(file + ": --set key '" + walked + "': parent is not an object");
      }
      node = &(*node)[name];
    }
    if (k + 1 < path.size() && node->is_null()) *node = json::object();
  }
  *node = value;
}

Scene load_scene_file(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path);
  if (!in) throw SceneError(path + ": cannot open the scene file");
  json document;
  try {
    document = json::parse(in, nullptr, true, /*ignore_comments=*/true);
  } catch (const json::parse_error& e) {
    // nlohmann reports "line L, column C" in its message
    std::string what = e.what();
    const auto at = what.find("line ");
    throw SceneError(
        path + ": JSON syntax error at " +
        (at == std::string::npos ? "byte " + std::to_string(e.byte) : what.substr(at)));
  }
  for (const auto& assignment : overrides) apply_override(document, assignment, path);
  return scene_from_json(document, path);
}

}  // namespace chainmail
