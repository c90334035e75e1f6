// Scene text: reading a scene file safely, strict JSON parsing, --set overrides, and the
// one-line message helpers the reader shares.
#include "scene_file/scene_file_text.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "core/scene.hpp"
#include "scene_file/strict_json.hpp"

namespace chainmail {

using json = nlohmann::json;

namespace {

bool valid_utf8(const std::string& text) {
  try {
    (void)json(text).dump();
    return true;
  } catch (const json::type_error&) {
    return false;
  }
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

std::string shown(const std::string& text, std::size_t limit) {
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

std::string show_number(double x) {
  char buffer[32];
  for (int precision = 6; precision <= 17; ++precision) {
    std::snprintf(buffer, sizeof buffer, "%.*g", precision, x);
    if (std::strtod(buffer, nullptr) == x) break;
  }
  return buffer;
}

bool integer_in(const json& value, long long min, long long max) {
  if (value.is_number_unsigned()) {
    const std::uint64_t u = value.get<std::uint64_t>();
    return max >= 0 && u <= static_cast<std::uint64_t>(max) &&
           (min <= 0 || u >= static_cast<std::uint64_t>(min));
  }
  const long long s = value.get<long long>();
  return s >= min && s <= max;
}

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

}  // namespace chainmail
