#include "core/scene.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <set>
#include <system_error>

#include "core/weave.hpp"

namespace chainmail {
namespace {

using json = nlohmann::json;

bool valid_utf8(const std::string& text) {
  try {
    (void)json(text).dump();
    return true;
  } catch (const json::type_error&) {
    return false;
  }
}

// text as it may appear in a one-line message: control characters escaped, invalid utf-8
// replaced, long text cut
std::string shown(const std::string& text, std::size_t limit = 80) {
  std::string out;
  for (const char ch : text) {
    const auto byte = static_cast<unsigned char>(ch);
    char code[8];
    std::snprintf(code, sizeof code, "\\x%02x", byte);
    out += byte < 0x20 || byte == 0x7f ? std::string(code) : std::string(1, ch);
  }
  if (!valid_utf8(out)) {
    out = json(out).dump(-1, ' ', false, json::error_handler_t::replace);
    out = out.substr(1, out.size() - 2);  // without the quotes
  }
  if (out.size() <= limit) return out;
  std::size_t cut = limit - 3;
  while (cut > 0 && (static_cast<unsigned char>(out[cut]) & 0xC0) == 0x80) --cut;  // utf-8 start
  return out.substr(0, cut) + "...";
}

// shortest text that reads back as the same double ("1e-06", "0.9", "1.9999999375")
std::string show_number(double x) {
  char buffer[32];
  for (int precision = 6; precision <= 17; ++precision) {
    std::snprintf(buffer, sizeof buffer, "%.*g", precision, x);
    if (std::strtod(buffer, nullptr) == x) break;
  }
  return buffer;
}

// whether an integer JSON value lies in [min, max]; parsed non-negative integers are unsigned,
// so 2^63 and above are compared as such, not wrapped
bool integer_in(const json& value, long long min, long long max) {
  if (value.is_number_unsigned()) {
    const std::uint64_t u = value.get<std::uint64_t>();
    return max >= 0 && u <= static_cast<std::uint64_t>(max) &&
           (min <= 0 || u >= static_cast<std::uint64_t>(min));
  }
  const long long s = value.get<long long>();
  return s >= min && s <= max;
}

// follows nlohmann's parse events to refuse what plain parsing accepts (duplicate keys, deep
// nesting) and to know the key path where the parser itself fails (a number out of range).
// nlohmann's parser and destructor are iterative, so refusing depth here bounds all recursion
class StrictParse {
 public:
  // where: message prefix ("f.json: key"); base: key path the text sits at; max_depth: containers
  StrictParse(std::string where, std::string base, int max_depth)
      : where_(std::move(where)), base_(std::move(base)), max_depth_(max_depth) {}

  // json::parse_error (syntax) escapes: the caller decides what a syntax error means
  json parse(const std::string& text, bool comments) {
    try {
      return json::parse(
          text, [this](int, json::parse_event_t event, json& parsed) { return on(event, parsed); },
          true, comments);
    } catch (const json::out_of_range& e) {
      // 406: a number beyond double range; nlohmann quotes the token
      const std::string what = e.what();
      const auto open = what.find('\''), close = what.rfind('\'');
      fail(open < close
               ? "number out of range: " + shown(what.substr(open + 1, close - open - 1), 40)
               : shown(what));
    }
  }

 private:
  struct Frame {
    bool array = false;
    std::string key;        // object: the key being read
    std::size_t index = 0;  // array: the element being read
    std::set<std::string> keys;
  };

  bool on(json::parse_event_t event, const json& parsed) {
    using Event = json::parse_event_t;
    switch (event) {
      case Event::object_start:
      case Event::array_start:
        if (static_cast<int>(frames_.size()) >= max_depth_) {
          fail("nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
        }
        frames_.push_back(Frame{event == Event::array_start, {}, 0, {}});
        break;
      case Event::key: {
        Frame& frame = frames_.back();
        frame.key = parsed.get<std::string>();
        if (!frame.keys.insert(frame.key).second) fail("duplicate key");
        break;
      }
      case Event::object_end:
      case Event::array_end:
        frames_.pop_back();
        element_done();
        break;
      case Event::value:
        element_done();
        break;
    }
    return true;
  }
  void element_done() {
    if (!frames_.empty() && frames_.back().array) ++frames_.back().index;
  }
  std::string path() const {
    std::string out = base_;
    for (const Frame& frame : frames_) {
      if (frame.array) {
        out += "[" + std::to_string(frame.index) + "]";
      } else {
        out += (out.empty() ? "" : ".") + frame.key;
      }
    }
    return out.empty() ? "(top level)" : out;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw SceneError(where_ + " '" + shown(path()) + "': " + what);
  }

  std::string where_, base_;
  int max_depth_;
  std::vector<Frame> frames_;
};

// deepest container nesting of a document (one built in code may skip the parser), iteratively
int nesting_depth(const json& document) {
  int deepest = 0;
  std::vector<std::pair<const json*, int>> stack{{&document, 0}};
  while (!stack.empty() && deepest <= kMaxJsonDepth) {
    const auto [node, depth] = stack.back();
    stack.pop_back();
    if (!node->is_structured()) continue;
    deepest = std::max(deepest, depth + 1);
    for (const json& child : *node) stack.push_back({&child, depth + 1});
  }
  return deepest;
}

// a file descriptor closed on every way out
struct FileDescriptor {
  int fd = -1;
  ~FileDescriptor() {
    if (fd >= 0) ::close(fd);
  }
};

std::string file_kind(mode_t mode) {
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  return "not a plain file";
}

// the whole scene file: stat() first so that a FIFO or device is never opened (opening a FIFO
// blocks), then read with a size cap (files in /proc report size 0)
std::string read_scene_text(const std::string& path) {
  auto fail = [&](const std::string& what) { throw SceneError(path + ": " + what); };
  auto system_error = [](int code) { return std::generic_category().message(code); };
  const std::string too_large = "is larger than the " + std::to_string(kMaxSceneFileBytes >> 20) +
                                " MiB limit for scene files";
  if (path.empty()) throw SceneError("scene file: the path is empty");
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) fail("cannot open the scene file: " + system_error(errno));
  if (S_ISDIR(info.st_mode)) fail("is a directory, not a scene file");
  if (!S_ISREG(info.st_mode)) fail("is not a regular file (" + file_kind(info.st_mode) + ")");
  if (info.st_size > kMaxSceneFileBytes) fail(too_large);
  // O_NONBLOCK: should the path become a FIFO after the stat, the open still does not block
  FileDescriptor file{::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK)};
  if (file.fd < 0) fail("cannot open the scene file: " + system_error(errno));
  if (::fstat(file.fd, &info) != 0 || !S_ISREG(info.st_mode)) fail("is not a regular file");
  std::string text;
  char buffer[1 << 16];
  while (true) {
    const ssize_t n = ::read(file.fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail("cannot read the scene file: " + system_error(errno));
    if (n == 0) break;
    if (static_cast<long long>(text.size()) + n > kMaxSceneFileBytes) fail(too_large);
    text.append(buffer, static_cast<size_t>(n));
  }
  // the JSON parser stops at a NUL byte: whatever follows it would be silently ignored
  if (const auto at = text.find('\0'); at != std::string::npos)
    fail("has a NUL byte at offset " + std::to_string(at) + " (not a JSON text file)");
  return text;
}

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
      if (!integer_in(*value, min, max)) {
        fail(key_path(key), "must be in [" + std::to_string(min) + ", " + std::to_string(max) +
                                "], got " + value->dump());  // as written: 2^63 is not negative
      }
      x = value->get<int>();
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
      fail(key_path(key), "must be one of " + list + ", got \"" + shown(x) + "\"");
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
  json& resolved() { return resolved_; }

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
  // lower bounds keep mass (density 2 pi^2 c a^2) and inertia normal doubles
  const double wd = r.number("wire_diameter", 0.0016, kMinLength, 1.0);
  const double id = r.number("inner_diameter", 0.008, kMinLength, 10.0);
  const double density = r.number("density", 7850.0, kMinDensity, 1e5);
  scene.ring_friction = r.number("friction", 0.3, 0.0, 10.0);
  r.finish();
  scene.ring = RingGeometry::from_diameters(wd, id, density);
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
  json& out = top.resolved()["weave"];
  const json* node = top.child("weave", true);
  Reader r(*node, "weave", scene.file, out);
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
  json& out = top.resolved()["pins"] = json::array();
  if (!pins) return;
  const int rows = scene.weave.type == WeaveType::chain ? 1 : scene.weave.rows;
  const int cols = scene.weave.cols;
  for (size_t p = 0; p < pins->size(); ++p) {
    json resolved;
    Reader r((*pins)[p], "pins[" + std::to_string(p) + "]", scene.file, resolved);
    PinSpec pin;
    const int kinds = r.has("ring") + r.has("edge") + r.has("corner");
    if (kinds != 1) r.fail(r.key_path("ring"), "a pin names exactly one of ring, edge, corner");
    if (r.has("ring") && (*pins)[p]["ring"].is_number_integer()) {
      // a ring by its index in the weave (row-major: row * cols + col)
      pin.kind = PinSpec::Kind::ring;
      const int index = r.integer("ring", std::nullopt, 0, rows * cols - 1);
      pin.row = index / cols;
      pin.col = index % cols;
      resolved["ring"] = {pin.row, pin.col};
    } else if (r.has("ring")) {
      pin.kind = PinSpec::Kind::ring;
      const auto [row, col] =
          r.ring_cell("ring", "must be a ring index or [row, col] integers", rows, cols);
      pin.row = row;
      pin.col = col;
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
    out.push_back(resolved);
  }
}

void read_support_and_loads(Scene& scene, Reader& top) {
  json& resolved = top.resolved();
  if (const json* support = top.child("support", false)) {
    Reader r(*support, "support", scene.file, resolved["support"]);
    Support s;
    s.center = r.vec3("center", std::nullopt);
    s.radius = r.number("radius", std::nullopt, kMinLength, 1e3);
    r.finish();
    scene.support = s;
  }
  const json* loads = top.array("loads");
  if (!loads) return;
  json& out = resolved["loads"] = json::array();
  const int rows = scene.weave.type == WeaveType::chain ? 1 : scene.weave.rows;
  for (size_t k = 0; k < loads->size(); ++k) {
    json entry;
    Reader r((*loads)[k], "loads[" + std::to_string(k) + "]", scene.file, entry);
    Load load;
    const auto [row, col] =
        r.ring_cell("ring", "must be [row, col] integers", rows, scene.weave.cols);
    load.row = row;
    load.col = col;
    entry["ring"] = {load.row, load.col};
    load.mass_factor = r.number("mass_factor", std::nullopt, 1e-3, 1e6);
    r.finish();
    scene.loads.push_back(load);
    out.push_back(entry);
  }
}

// the small optional sections: features, output, camera, stability
void read_settings(Scene& scene, Reader& top) {
  json& resolved = top.resolved();
  const json empty = json::object();
  auto section = [&](const std::string& key) {
    const json* node = top.child(key, false);
    return Reader(node ? *node : empty, key, scene.file, resolved[key]);
  };
  {
    Reader r = section("features");
    scene.self_contact = r.boolean("self_contact", true);
    r.finish();
  }
  {
    Reader r = section("output");
    scene.write_frames = r.boolean("frames", false);
    r.finish();
  }
  {
    Reader r = section("camera");
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
  Reader r = section("stability");
  scene.stability.max_speed = r.number("max_speed", 20.0, 0.0, 1e6, true);
  scene.stability.links_must_hold = r.boolean("links_must_hold", true);
  scene.stability.max_stretch = r.number("max_stretch", 1.25, 1.0, 1e3);
  scene.stability.energy_growth = r.number("energy_growth", 1.5, 1.0, 1e6);
  r.finish();
}

// the elements of a --set key ("colliders.0.radius"), every one non-empty
std::vector<std::string> split_override_key(const std::string& key, const std::string& file) {
  const std::string where = file + ": --set key '" + shown(key) + "': ";
  std::vector<std::string> path;
  for (std::size_t start = 0;;) {
    const std::size_t dot = key.find('.', start);
    // npos - start: the rest of the key; a trailing dot leaves an empty last element
    path.push_back(key.substr(start, dot == std::string::npos ? dot : dot - start));
    if (path.back().empty()) {
      throw SceneError(where + "empty path element (no leading, trailing or double dots)");
    }
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  if (path.size() > static_cast<std::size_t>(kMaxJsonDepth)) {
    throw SceneError(where + "nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
  }
  return path;
}

// the node a --set path names, creating objects on the way
json& override_target(json& document, const std::vector<std::string>& path,
                      const std::string& file) {
  json* node = &document;
  std::string walked;
  for (size_t k = 0; k < path.size(); ++k) {
    const std::string& name = path[k];
    walked += (k == 0 ? "" : ".") + name;
    const std::string where = file + ": --set key '" + shown(walked) + "': ";
    if (node->is_array()) {
      // digits only: stoul would take "1x" as 1 and "-1" as a huge index
      if (name.find_first_not_of("0123456789") != std::string::npos) {
        throw SceneError(where + "expected an array index");
      }
      if (name.size() > 9 || std::stoul(name) >= node->size()) {
        throw SceneError(where + "index out of range");
      }
      node = &(*node)[std::stoul(name)];
    } else {
      if (!node->is_object()) throw SceneError(where + "parent is not an object");
      node = &(*node)[name];
    }
    if (k + 1 < path.size() && node->is_null()) *node = json::object();
  }
  return *node;
}

// a --set value: strict JSON when it parses as JSON (numbers, true, [1,2,3]), else a plain
// string. JSON that strict parsing refuses (1e400, duplicate keys, nesting) is an error: a value
// that looks like a number must not quietly become the string "1e400"
json override_value(const std::string& text, const std::string& key, std::size_t depth,
                    const std::string& file) {
  const int budget = kMaxJsonDepth - static_cast<int>(depth);  // the path is nesting too
  try {
    return StrictParse(file + ": --set key", key, budget).parse(text, /*comments=*/false);
  } catch (const json::parse_error&) {
  }
  // written into summary.json later: invalid utf-8 would fail there (nlohmann type_error)
  if (!valid_utf8(text)) {
    throw SceneError(file + ": --set key '" + shown(key) + "': value is not valid UTF-8");
  }
  return text;
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

json parse_json_strict(const std::string& text, const std::string& source) {
  try {
    return StrictParse(source + ": key", "", kMaxJsonDepth).parse(text, /*comments=*/true);
  } catch (const json::parse_error& e) {
    // nlohmann reports "line L, column C" in its message
    std::string what = e.what();
    const auto at = what.find("line ");
    throw SceneError(
        source + ": JSON syntax error at " +
        (at == std::string::npos ? "byte " + std::to_string(e.byte) : shown(what.substr(at), 200)));
  }
}

Scene scene_from_json(const json& document, const std::string& file) {
  // a document built in code skips the parser's depth limit; copies below recurse
  if (nesting_depth(document) > kMaxJsonDepth) {
    throw SceneError(file + ": key '(top level)': nested deeper than " +
                     std::to_string(kMaxJsonDepth) + " levels");
  }
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
  read_support_and_loads(scene, top);
  scene.initial_velocity = top.vec3("initial_velocity", Vec3::Zero(), -1e3, 1e3);
  scene.gravity = top.vec3("gravity", Vec3(0.0, -9.81, 0.0), -1e4, 1e4);
  scene.duration = top.number("duration", std::nullopt, 0.0, 1e5, true);
  scene.sample_interval = top.number("sample_interval", 0.05, 0.0, 1e5, true);
  read_settings(scene, top);
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
  scene.resolved = resolved;
  return scene;
}

void apply_override(json& document, const std::string& assignment, const std::string& file) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos) {
    throw SceneError(file + ": --set '" + shown(assignment) + "': expected KEY=VALUE");
  }
  if (eq == 0) {
    throw SceneError(file + ": --set '" + shown(assignment) + "': empty key (expected KEY=VALUE)");
  }
  const std::string key = assignment.substr(0, eq);
  if (!valid_utf8(key)) {
    throw SceneError(file + ": --set key '" + shown(key) + "': key is not valid UTF-8");
  }
  const std::vector<std::string> path = split_override_key(key, file);
  json value = override_value(assignment.substr(eq + 1), key, path.size(), file);
  override_target(document, path, file) = std::move(value);
}

Scene load_scene_file(const std::string& path, const std::vector<std::string>& overrides) {
  json document = parse_json_strict(read_scene_text(path), path);
  for (const auto& assignment : overrides) apply_override(document, assignment, path);
  return scene_from_json(document, path);
}

}  // namespace chainmail
