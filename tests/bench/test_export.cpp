// Frame export: the .glb parses back as glTF 2.0 (one torus mesh, an animated node per ring, one
// GPU-instanced node) with the frames in its animation; the .npz is a zip of .npy arrays with
// the frames in them. Both are read back here byte by byte.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <vector>

#include "bench/harness/common/usage_error.hpp"
#include "bench/harness/output/export.hpp"
#include "core/weave.hpp"
#include "glb_reader.hpp"
#include "test_temp.hpp"

namespace chainmail {
namespace {

namespace fs = std::filesystem;
using test::Glb;

// a 3 x 3 sheet whose rings drift along +x at 0.2 m/s and turn about their axis at 3 rad/s;
// ring 0's quaternion is given negated in frame 2 (the same rotation); frame 3 repeats frame 2's
// time
struct Moving {
  Scene scene;
  Weave weave;
  std::vector<double> times = {0.0, 0.1, 0.2, 0.2, 0.3};
  Moving() {
    scene.name = "moving";
    scene.ring = RingGeometry::from_diameters(0.0016, 0.008, 7850.0);
    scene.weave.rows = 3, scene.weave.cols = 3;
    weave = make_weave(scene.weave, scene.ring);
  }
  RingFrame frame(std::size_t k) const {
    RingFrame f;
    f.resize(weave.size());
    f.velocity.setZero();
    f.t = times[k];
    for (int ring = 0; ring < weave.size(); ++ring) {
      f.position.col(ring) = weave.rest_position.col(ring) + Vec3(0.2 * f.t, 0.0, 0.0);
      const Quat rest(weave.rest_orientation(0, ring), weave.rest_orientation(1, ring),
                      weave.rest_orientation(2, ring), weave.rest_orientation(3, ring));
      f.set_quat(ring, rest * Quat(Eigen::AngleAxisd(3.0 * f.t, Vec3::UnitY())));
    }
    if (k == 2) f.orientation.col(0) *= -1.0;
    return f;
  }
  FrameSequence sequence() const {
    return {times.size(), [this](std::size_t k, RingFrame& f) {
              f = frame(k);
              return true;
            }};
  }
};

struct TempDir {
  fs::path path = chainmail::test_temp_root() /
                  ("chainmail_test_export_" +
                   std::string(testing::UnitTest::GetInstance()->current_test_info()->name()));
  TempDir() {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

TEST(Export, GlbHoldsOneMeshAnAnimatedNodePerRingAndTheFirstFrameInstanced) {
  const Moving moving;
  TempDir dir;
  const std::string path = (dir.path / "moving.glb").string();
  write_glb({moving.scene, moving.weave, "plausible"}, moving.sequence(), path);
  const Glb glb = test::read_glb(path);
  ASSERT_TRUE(glb.doc.is_object());
  const int rings = moving.weave.size();
  EXPECT_EQ(glb.doc["asset"]["version"], "2.0");
  ASSERT_EQ(glb.doc["meshes"].size(), 1u);

  // the mesh is the ring's torus: every vertex a wire radius from the centre circle, in bounds
  const int position = glb.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"];
  const std::vector<float> vertices = glb.floats(position);
  const double a = moving.scene.ring.wire_radius, c = moving.scene.ring.centre_radius;
  for (std::size_t v = 0; v < vertices.size(); v += 3) {
    const double radial = std::hypot(vertices[v], vertices[v + 2]) - c;
    ASSERT_NEAR(std::hypot(radial, vertices[v + 1]), a, 1e-6 * c);
  }
  EXPECT_NEAR(glb.doc["accessors"][position]["max"][0].get<double>(), a + c, 1e-7);
  EXPECT_NEAR(glb.doc["accessors"][position]["min"][1].get<double>(), -a, 1e-7);

  // the default scene: a root with one node per ring, all using mesh 0
  const nlohmann::json& root = glb.doc["nodes"][glb.doc["scenes"][0]["nodes"][0].get<int>()];
  ASSERT_EQ(root["children"].size(), static_cast<std::size_t>(rings));
  for (int child : root["children"]) EXPECT_EQ(glb.doc["nodes"][child]["mesh"], 0);

  // the instanced node: alone in scene 1, as many instances as rings, frame 0's poses
  const int instanced = test::instanced_node(glb);
  ASSERT_GE(instanced, 0);
  EXPECT_EQ(glb.doc["scenes"][1]["nodes"][0], instanced);
  EXPECT_EQ(glb.doc["nodes"][instanced]["mesh"], 0);
  const auto& attributes =
      glb.doc["nodes"][instanced]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"];
  const std::vector<float> where = glb.floats(attributes["TRANSLATION"]);
  ASSERT_EQ(where.size(), 3u * rings);
  EXPECT_EQ(glb.floats(attributes["ROTATION"]).size(), 4u * rings);
  for (int ring = 0; ring < rings; ++ring)
    EXPECT_EQ(where[3 * ring], static_cast<float>(moving.weave.rest_position(0, ring)));
}

TEST(Export, GlbAnimationKeysAreTheFramesWithContinuousRotations) {
  const Moving moving;
  TempDir dir;
  const std::string path = (dir.path / "moving.glb").string();
  write_glb({moving.scene, moving.weave, "plausible"}, moving.sequence(), path);
  const Glb glb = test::read_glb(path);
  const nlohmann::json& animation = glb.doc["animations"][0];
  const int rings = moving.weave.size();
  ASSERT_EQ(animation["channels"].size(), 2u * rings);
  // the repeated time is dropped: keys must increase strictly
  const int input = animation["samplers"][0]["input"];
  EXPECT_EQ(glb.floats(input), (std::vector<float>{0.0f, 0.1f, 0.2f, 0.3f}));
  EXPECT_EQ(glb.doc["accessors"][input]["max"][0], 0.3f);
  const std::vector<std::size_t> frames = {0, 1, 2, 4};
  for (const nlohmann::json& channel : animation["channels"]) {
    const nlohmann::json& node = glb.doc["nodes"][channel["target"]["node"].get<int>()];
    const int ring = std::stoi(node["name"].get<std::string>().substr(5));
    const std::vector<float> keys =
        glb.floats(animation["samplers"][channel["sampler"].get<int>()]["output"]);
    for (std::size_t k = 0; k < frames.size(); ++k) {
      const RingFrame f = moving.frame(frames[k]);
      if (channel["target"]["path"] == "translation") {
        for (int axis = 0; axis < 3; ++axis)
          ASSERT_EQ(keys[3 * k + axis], static_cast<float>(f.position(axis, ring)));
        continue;
      }
      // (x, y, z, w), the same rotation as the frame's, on the side of the previous key
      const Eigen::Vector4d wxyz = f.orientation.col(ring);
      const Eigen::Vector4d q(keys[4 * k + 3], keys[4 * k], keys[4 * k + 1], keys[4 * k + 2]);
      ASSERT_NEAR(std::abs(q.dot(wxyz)), 1.0, 1e-6) << "ring " << ring << " key " << k;
      if (k > 0) {
        const Eigen::Vector4d p(keys[4 * k - 1], keys[4 * k - 4], keys[4 * k - 3], keys[4 * k - 2]);
        ASSERT_GT(q.dot(p), 0.0) << "ring " << ring << " flips at key " << k;
      }
    }
  }
}

// a stored zip's entries by name: the bytes of each (local headers walked from the start)
std::map<std::string, std::string> zip_entries(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::map<std::string, std::string> entries;
  std::size_t at = 0;
  auto u32 = [&](std::size_t k) {
    std::uint32_t v;
    std::memcpy(&v, bytes.data() + k, 4);
    return v;
  };
  while (at + 30 <= bytes.size() && u32(at) == 0x04034b50u) {
    const std::uint32_t size = u32(at + 18);
    const std::uint16_t name_length = static_cast<std::uint16_t>(u32(at + 26) & 0xffff);
    EXPECT_EQ(u32(at + 8) >> 16, 0u) << "stored, not compressed";
    const std::string name = bytes.substr(at + 30, name_length);
    entries[name] = bytes.substr(at + 30 + name_length, size);
    at += 30 + name_length + size;
  }
  EXPECT_EQ(u32(at), 0x02014b50u) << "central directory after the entries";
  return entries;
}

TEST(Export, NpzIsAStoredZipOfNpyArraysHoldingTheFrames) {
  const Moving moving;
  TempDir dir;
  const std::string path = (dir.path / "moving.npz").string();
  write_npz({moving.scene, moving.weave, "plausible"}, moving.sequence(), path);
  const auto entries = zip_entries(path);
  for (const char* name : {"t.npy", "position.npy", "orientation.npy", "grid.npy",
                           "wire_radius.npy", "centre_radius.npy"})
    EXPECT_TRUE(entries.count(name)) << name;
  const std::string& position = entries.at("position.npy");
  ASSERT_EQ(position.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
  const std::size_t header =
      10 + static_cast<unsigned char>(position[8]) + 256 * static_cast<unsigned char>(position[9]);
  EXPECT_EQ(header % 64, 0u);
  EXPECT_NE(position.find("'shape': (5, 9, 3)"), std::string::npos) << position.substr(0, header);
  EXPECT_NE(position.find("'descr': '<f8'"), std::string::npos);
  ASSERT_EQ(position.size(), header + 5 * 9 * 3 * 8);
  // the frames as written, at full precision: ring 4 of frame 3
  double xyz[3];
  std::memcpy(xyz, position.data() + header + 8 * 3 * (3 * 9 + 4), sizeof xyz);
  for (int axis = 0; axis < 3; ++axis) EXPECT_EQ(xyz[axis], moving.frame(3).position(axis, 4));
  EXPECT_NE(entries.at("t.npy").find("'shape': (5,)"), std::string::npos);
  EXPECT_NE(entries.at("wire_radius.npy").find("'shape': ()"), std::string::npos);
  EXPECT_NE(entries.at("grid.npy").find("'descr': '<i8'"), std::string::npos);
}

TEST(Export, FormatsAreGltfAndNpzAndAnythingElseIsRefused) {
  EXPECT_EQ(parse_export_formats({"npz", "gltf", "npz"}),
            (std::vector<ExportFormat>{ExportFormat::npz, ExportFormat::gltf}));
  EXPECT_THROW(parse_export_formats({"obj"}), UsageError);
  const Moving moving;
  EXPECT_EQ(export_size_refusal(moving.weave, 1000), "");
  // 9 rings x 32 bytes of orientation per sample: past 4 GiB at 15 million samples
  EXPECT_NE(export_size_refusal(moving.weave, 15'000'000), "");
}

}  // namespace
}  // namespace chainmail
