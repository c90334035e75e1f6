// glTF 2.0 binary export. Layout and why:
// - one mesh, the ring's torus, used by one node per ring: core glTF animates node translation and
//   rotation, and every importer (Blender, three.js, Babylon, ...) plays that. The frames are one
//   animation with a translation and a rotation channel per ring, all on one shared time input.
// - EXT_mesh_gpu_instancing cannot be animated (the extension lists per-instance animation as a
//   current limitation), so the GPU-instanced rings are a second scene: one node carrying the
//   first frame as N instances. Importers show the default scene (the animated one); the
//   instanced one becomes a scene of its own (Blender) or gltf.scenes[1] (three.js), never drawn
//   on top of the first. The extension is used, not required: a loader without it still loads.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/harness/common/version.hpp"
#include "bench/harness/output/export.hpp"
#include "bench/harness/output/output.hpp"
#include "core/ring.hpp"

namespace chainmail {
namespace {

using json = nlohmann::json;
static_assert(std::endian::native == std::endian::little, "glTF buffers are little-endian");

constexpr std::uint32_t kGlbMagic = 0x46546c67;  // "glTF"
constexpr std::uint32_t kChunkJson = 0x4e4f534a, kChunkBin = 0x004e4942;
constexpr int kFloat = 5126, kUnsignedShort = 5123, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;
constexpr int kSurfaceAround = 32, kSurfaceAcross = 12;  // torus segments: ring, wire
// a steel look for the exported rings (linear RGB, as the renderer's steel)
constexpr float kSteel[4] = {0.62f, 0.64f, 0.67f, 1.0f};

// the binary chunk as it fills, and the buffer views and accessors that describe it
struct Buffers {
  std::vector<unsigned char> bin;
  json views = json::array(), accessors = json::array();

  // `bytes` appended as one buffer view (4-byte aligned; target 0: none); returns its index
  int view(const void* data, std::size_t bytes, int target) {
    while (bin.size() % 4) bin.push_back(0);
    json entry = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}};
    if (target) entry["target"] = target;
    const auto* first = static_cast<const unsigned char*>(data);
    bin.insert(bin.end(), first, first + bytes);
    views.push_back(entry);
    return static_cast<int>(views.size()) - 1;
  }
  // an accessor of `count` elements of `type` at `offset` bytes into view `view`
  int accessor(int view, std::size_t offset, int component, std::size_t count, const char* type) {
    accessors.push_back({{"bufferView", view},
                         {"byteOffset", offset},
                         {"componentType", component},
                         {"count", count},
                         {"type", type}});
    return static_cast<int>(accessors.size()) - 1;
  }
};

// per-component bounds of `count` vectors of `width` floats (glTF requires them on positions and
// animation inputs)
void add_bounds(json& accessor, const float* data, std::size_t count, int width) {
  json lo = json::array(), hi = json::array();
  for (int c = 0; c < width; ++c) {
    float a = data[c], b = data[c];
    for (std::size_t k = 1; k < count; ++k) {
      a = std::min(a, data[k * width + c]);
      b = std::max(b, data[k * width + c]);
    }
    lo.push_back(a);
    hi.push_back(b);
  }
  accessor["min"] = lo;
  accessor["max"] = hi;
}

// the frames as glTF wants them, ring by ring: times, translations, rotations (x, y, z, w)
struct Tracks {
  std::vector<float> time;         // (F) s
  std::vector<float> translation;  // (N, F, 3) m
  std::vector<float> rotation;     // (N, F, 4) unit, sign-continuous along each ring's track
};

Tracks read_tracks(const FrameSequence& frames, int rings) {
  Tracks tracks;
  const std::size_t capacity = frames.count, n = static_cast<std::size_t>(rings);
  tracks.translation.resize(n * capacity * 3);
  tracks.rotation.resize(n * capacity * 4);
  std::vector<Eigen::Vector4d> previous(n, Eigen::Vector4d::Zero());
  RingFrame frame;
  for (std::size_t k = 0; k < frames.count; ++k) {
    if (!frames.read(k, frame)) throw std::runtime_error("cannot read frame " + std::to_string(k));
    // animation inputs must increase strictly, also as floats
    if (!tracks.time.empty() && !(static_cast<float>(frame.t) > tracks.time.back())) continue;
    const std::size_t kept = tracks.time.size();
    tracks.time.push_back(static_cast<float>(frame.t));
    for (std::size_t ring = 0; ring < n; ++ring) {
      const std::size_t at = ring * capacity + kept;
      for (int c = 0; c < 3; ++c)
        tracks.translation[3 * at + c] = static_cast<float>(frame.position(c, ring));
      // (w, x, y, z) -> (x, y, z, w), unit; q and -q are one rotation, but importers that
      // interpolate components (Blender) need neighbouring keys on the same side
      const Eigen::Vector4d wxyz = frame.orientation.col(ring).normalized();
      Eigen::Vector4d q(wxyz[1], wxyz[2], wxyz[3], wxyz[0]);
      if (q.dot(previous[ring]) < 0.0) q = -q;
      previous[ring] = q;
      for (int c = 0; c < 4; ++c) tracks.rotation[4 * at + c] = static_cast<float>(q[c]);
    }
  }
  // rings' tracks back to back when frames were skipped
  const std::size_t count = tracks.time.size();
  for (std::size_t ring = 1; ring < n && count < capacity; ++ring) {
    std::memmove(&tracks.translation[3 * ring * count], &tracks.translation[3 * ring * capacity],
                 12 * count);
    std::memmove(&tracks.rotation[4 * ring * count], &tracks.rotation[4 * ring * capacity],
                 16 * count);
  }
  tracks.translation.resize(n * count * 3);
  tracks.rotation.resize(n * count * 4);
  return tracks;
}

// the ring's torus as mesh 0 with a steel material
json ring_mesh(const RingGeometry& ring, Buffers& buffers) {
  const RingSurface surface =
      ring_surface(ring.wire_radius, ring.centre_radius, kSurfaceAround, kSurfaceAcross);
  const auto vertices = static_cast<std::size_t>(surface.vertices());
  const int position_view =
      buffers.view(surface.position.data(), surface.position.size() * 4, kArrayBuffer);
  const int position = buffers.accessor(position_view, 0, kFloat, vertices, "VEC3");
  add_bounds(buffers.accessors[position], surface.position.data(), vertices, 3);
  const int normal =
      buffers.accessor(buffers.view(surface.normal.data(), surface.normal.size() * 4, kArrayBuffer),
                       0, kFloat, vertices, "VEC3");
  std::vector<std::uint16_t> small(surface.index.begin(), surface.index.end());
  const bool fits = vertices <= 0xffff;
  const int index_view =
      fits ? buffers.view(small.data(), small.size() * 2, kElementArrayBuffer)
           : buffers.view(surface.index.data(), surface.index.size() * 4, kElementArrayBuffer);
  const int index = buffers.accessor(index_view, 0, fits ? kUnsignedShort : kUnsignedInt,
                                     surface.index.size(), "SCALAR");
  json primitive = {{"attributes", {{"POSITION", position}, {"NORMAL", normal}}},
                    {"indices", index},
                    {"material", 0}};
  return {{"name", "ring"}, {"primitives", json::array({primitive})}};
}

// one node per ring (first frame as its rest pose) under a root, and their animation
void animated_rings(const ExportSource& source, const Tracks& tracks, Buffers& buffers,
                    json& document) {
  const int rings = source.weave.size();
  const std::size_t count = tracks.time.size();
  const int time = buffers.accessor(buffers.view(tracks.time.data(), tracks.time.size() * 4, 0), 0,
                                    kFloat, count, "SCALAR");
  add_bounds(buffers.accessors[time], tracks.time.data(), count, 1);
  const int moves = buffers.view(tracks.translation.data(), tracks.translation.size() * 4, 0);
  const int turns = buffers.view(tracks.rotation.data(), tracks.rotation.size() * 4, 0);
  json root = {{"name", source.backend}, {"children", json::array()}};
  json samplers = json::array(), channels = json::array();
  for (int ring = 0; ring < rings; ++ring) {
    const std::size_t first = static_cast<std::size_t>(ring) * count;
    const int node = ring + 1;
    root["children"].push_back(node);
    const float* t = &tracks.translation[3 * first];
    const float* r = &tracks.rotation[4 * first];
    document["nodes"].push_back({{"name", "ring " + std::to_string(ring) + " (" +
                                              std::to_string(source.weave.grid[ring][0]) + ", " +
                                              std::to_string(source.weave.grid[ring][1]) + ")"},
                                 {"mesh", 0},
                                 {"translation", {t[0], t[1], t[2]}},
                                 {"rotation", {r[0], r[1], r[2], r[3]}}});
    const int move = buffers.accessor(moves, 12 * first, kFloat, count, "VEC3");
    const int turn = buffers.accessor(turns, 16 * first, kFloat, count, "VEC4");
    samplers.push_back({{"input", time}, {"output", move}, {"interpolation", "LINEAR"}});
    samplers.push_back({{"input", time}, {"output", turn}, {"interpolation", "LINEAR"}});
    channels.push_back(
        {{"sampler", 2 * ring}, {"target", {{"node", node}, {"path", "translation"}}}});
    channels.push_back(
        {{"sampler", 2 * ring + 1}, {"target", {{"node", node}, {"path", "rotation"}}}});
  }
  document["nodes"][0] = root;
  document["animations"] =
      json::array({{{"name", source.backend}, {"samplers", samplers}, {"channels", channels}}});
}

// the first frame as one node of GPU instances, in a scene of its own
int instanced_rings(const ExportSource& source, const Tracks& tracks, Buffers& buffers,
                    json& document) {
  const int rings = source.weave.size();
  const std::size_t count = tracks.time.size();
  std::vector<float> translation(3 * static_cast<std::size_t>(rings)),
      rotation(4 * static_cast<std::size_t>(rings));
  for (int ring = 0; ring < rings; ++ring) {
    const std::size_t first = static_cast<std::size_t>(ring) * count;
    std::memcpy(&translation[3 * ring], &tracks.translation[3 * first], 12);
    std::memcpy(&rotation[4 * ring], &tracks.rotation[4 * first], 16);
  }
  const int move = buffers.accessor(buffers.view(translation.data(), translation.size() * 4, 0), 0,
                                    kFloat, static_cast<std::size_t>(rings), "VEC3");
  const int turn = buffers.accessor(buffers.view(rotation.data(), rotation.size() * 4, 0), 0,
                                    kFloat, static_cast<std::size_t>(rings), "VEC4");
  document["nodes"].push_back(
      {{"name", source.backend + " rings, first frame (instanced)"},
       {"mesh", 0},
       {"extensions",
        {{"EXT_mesh_gpu_instancing",
          {{"attributes", {{"TRANSLATION", move}, {"ROTATION", turn}}}}}}}});
  return static_cast<int>(document["nodes"].size()) - 1;
}

// little-endian 32-bit words
void put32(std::string& out, std::uint32_t value) {
  out.append(reinterpret_cast<const char*>(&value), 4);
}

// header, JSON chunk (padded with spaces), BIN chunk (padded with zeros)
std::string glb_bytes(const json& document, std::vector<unsigned char> bin) {
  std::string text = document.dump();
  while (text.size() % 4) text.push_back(' ');
  while (bin.size() % 4) bin.push_back(0);
  std::string out;
  put32(out, kGlbMagic);
  put32(out, 2);
  put32(out, static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + bin.size()));
  put32(out, static_cast<std::uint32_t>(text.size()));
  put32(out, kChunkJson);
  out += text;
  put32(out, static_cast<std::uint32_t>(bin.size()));
  put32(out, kChunkBin);
  out.append(reinterpret_cast<const char*>(bin.data()), bin.size());
  return out;
}

}  // namespace

void write_glb(const ExportSource& source, const FrameSequence& frames, const std::string& path) {
  const Tracks tracks = read_tracks(frames, source.weave.size());
  if (tracks.time.empty()) throw std::runtime_error("no frames to export for " + source.backend);
  Buffers buffers;
  json document;
  document["asset"] = {{"version", "2.0"},
                       {"generator", "chainmail " + chainmail_version()},
                       {"extras",
                        {{"scene", source.scene.name},
                         {"backend", source.backend},
                         {"rings", source.weave.size()},
                         {"frames", tracks.time.size()}}}};
  document["extensionsUsed"] = json::array({"EXT_mesh_gpu_instancing"});
  document["materials"] = json::array(
      {{{"name", "steel"},
        {"pbrMetallicRoughness",
         {{"baseColorFactor", kSteel}, {"metallicFactor", 1.0}, {"roughnessFactor", 0.35}}}}});
  document["meshes"] = json::array({ring_mesh(source.scene.ring, buffers)});
  document["nodes"] = json::array({json::object()});  // the root, filled in by animated_rings
  animated_rings(source, tracks, buffers, document);
  const int instanced = instanced_rings(source, tracks, buffers, document);
  document["scene"] = 0;
  document["scenes"] = json::array(
      {{{"name", source.backend}, {"nodes", {0}}},
       {{"name", source.backend + ", first frame (GPU instances)"}, {"nodes", {instanced}}}});
  document["bufferViews"] = buffers.views;
  document["accessors"] = buffers.accessors;
  document["buffers"] = json::array({{{"byteLength", buffers.bin.size()}}});
  write_file_atomic(path, glb_bytes(document, std::move(buffers.bin)));
}

}  // namespace chainmail
