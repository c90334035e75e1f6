// A .glb read back for tests: the container checked against the glTF 2.0 binary layout, the JSON
// chunk parsed, and accessors read from the BIN chunk.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace chainmail::test {

struct Glb {
  nlohmann::json doc;
  std::vector<unsigned char> bin;

  // the floats of accessor `index` (component type FLOAT), count * components of them
  std::vector<float> floats(int index) const {
    const nlohmann::json& accessor = doc["accessors"][index];
    const nlohmann::json& view = doc["bufferViews"][accessor["bufferView"].get<int>()];
    const std::size_t offset = view.value("byteOffset", 0) + accessor.value("byteOffset", 0);
    const std::string type = accessor["type"];
    const std::size_t width = type == "SCALAR" ? 1 : type == "VEC3" ? 3 : type == "VEC4" ? 4 : 0;
    std::vector<float> out(accessor["count"].get<std::size_t>() * width);
    EXPECT_EQ(accessor["componentType"], 5126);
    EXPECT_LE(offset + 4 * out.size(), bin.size());
    if (offset + 4 * out.size() <= bin.size())
      std::memcpy(out.data(), bin.data() + offset, 4 * out.size());
    return out;
  }
};

inline std::uint32_t word(const std::vector<unsigned char>& bytes, std::size_t at) {
  std::uint32_t value = 0;
  std::memcpy(&value, bytes.data() + at, 4);
  return value;
}

// the file checked as a glb (header, a JSON chunk then a BIN chunk, 4-byte alignment); an empty
// Glb with a test failure when it is not one
inline Glb read_glb(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                         std::istreambuf_iterator<char>());
  Glb glb;
  EXPECT_GE(bytes.size(), 28u) << path;
  if (bytes.size() < 28) return glb;
  EXPECT_EQ(word(bytes, 0), 0x46546c67u) << "magic glTF";
  EXPECT_EQ(word(bytes, 4), 2u) << "version";
  EXPECT_EQ(word(bytes, 8), bytes.size()) << "length";
  const std::uint32_t json_length = word(bytes, 12);
  EXPECT_EQ(word(bytes, 16), 0x4e4f534au) << "JSON chunk";
  EXPECT_EQ(json_length % 4, 0u);
  const std::size_t bin_at = 20 + json_length;
  EXPECT_LE(bin_at + 8, bytes.size());
  if (bin_at + 8 > bytes.size()) return glb;
  glb.doc = nlohmann::json::parse(bytes.begin() + 20, bytes.begin() + bin_at);
  const std::uint32_t bin_length = word(bytes, bin_at);
  EXPECT_EQ(word(bytes, bin_at + 4), 0x004e4942u) << "BIN chunk";
  EXPECT_EQ(bin_length % 4, 0u);
  EXPECT_EQ(bin_at + 8 + bin_length, bytes.size());
  glb.bin.assign(bytes.begin() + bin_at + 8, bytes.end());
  EXPECT_LE(glb.doc["buffers"][0]["byteLength"].get<std::size_t>(), glb.bin.size());
  return glb;
}

// the node carrying EXT_mesh_gpu_instancing (-1 when none)
inline int instanced_node(const Glb& glb) {
  const nlohmann::json& nodes = glb.doc["nodes"];
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    if (nodes[k].contains("extensions") &&
        nodes[k]["extensions"].contains("EXT_mesh_gpu_instancing"))
      return static_cast<int>(k);
  }
  return -1;
}

}  // namespace chainmail::test
