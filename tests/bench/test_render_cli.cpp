// `chainmail render RUN_DIR` and `--export` as a user meets them: the run's own PNGs redrawn byte
// for byte, other sizes and panel orders, exports of a 16 x 16 curtain, and bad input refused
// with one line and nothing written.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <stdlib.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <tuple>
#include <vector>

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#endif
#include <stb/stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include "bench/harness/output/render_output.hpp"
#include "bench/harness/run/run.hpp"
#include "core/scene.hpp"
#include "glb_reader.hpp"
#include "scene_file/scene_file.hpp"
#include "test_temp.hpp"

namespace chainmail {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

struct Outcome {
  int status = -1;
  std::string output;  // stdout and stderr together
};

Outcome chainmail(const std::string& arguments) {
  Outcome outcome;
  const std::string line = CHAINMAIL_BINARY_DIR "/bench/chainmail " + arguments + " 2>&1";
  FILE* pipe = ::popen(line.c_str(), "r");
  if (!pipe) return outcome;
  char buffer[4096];
  for (size_t got; (got = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;)
    outcome.output.append(buffer, got);
  const int raw = ::pclose(pipe);
  outcome.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return outcome;
}

std::string bytes_of(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

struct Png {
  int width = 0, height = 0;
  std::vector<unsigned char> rgba;
};
Png load_png(const fs::path& path) {
  Png png;
  int channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &png.width, &png.height, &channels, 4);
  if (data) png.rgba.assign(data, data + static_cast<size_t>(png.width) * png.height * 4);
  stbi_image_free(data);
  return png;
}

class RenderCli : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = chainmail::test_temp_root() /
           ("chainmail_test_render_cli_" +
            std::string(testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // a 4 x 4 curtain through plausible and massspring, 0.05 s sampled every 0.025 s
  std::string scene(const json& change = json::object()) {
    json doc = {{"name", "cli"},
                {"weave", {{"type", "4in1"}, {"rows", 4}, {"cols", 4}, {"plane", "xy"}}},
                {"pins", json::array({{{"edge", "top"}}})},
                {"duration", 0.05},
                {"sample_interval", 0.025},
                {"backends", {{"plausible", json::object()}, {"massspring", {{"substeps", 10}}}}}};
    doc.merge_patch(change);
    const fs::path path = dir_ / "scene.json";
    std::ofstream(path) << doc.dump(2);
    return path.string();
  }
  // a run of scene() with `flags` into dir_/run; false (and the test skipped) without GL
  bool run(const std::string& flags) {
    const Outcome outcome = chainmail("run " + scene() + " --reference none --cache none --quiet " +
                                      flags + " --out " + path("run"));
    if (outcome.status == 2 && outcome.output.find("--render:") != std::string::npos) {
      skip_ = "no renderer here: " + outcome.output;
      return false;
    }
    // 1: a backend's verdict was not stable, which does not matter for drawing
    EXPECT_LE(outcome.status, 1) << outcome.output;
    return outcome.status <= 1;
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
  std::string skip_;
};

TEST_F(RenderCli, RedrawsTheRunsOwnImagesByteForByteAndAtOtherSizes) {
  if (!run("--frames --render")) GTEST_SKIP() << skip_;
  const Outcome again = chainmail("render " + path("run") + " --out " + path("again"));
  ASSERT_EQ(again.status, 0) << again.output;
  for (const char* image : {"00000.png", "00001.png", "00002.png"}) {
    const std::string original = bytes_of(dir_ / "run" / "images" / image);
    ASSERT_FALSE(original.empty()) << image;
    EXPECT_TRUE(original == bytes_of(dir_ / "again" / "images" / image)) << image << " differs";
  }
  for (const auto& [size, width, height] :
       {std::tuple{"640x360", 640, 360}, {"1920x1080", 1920, 1080}}) {
    const std::string out = path(std::string("size") + size);
    const Outcome sized = chainmail("render " + path("run") + " --size " + size + " --out " + out);
    ASSERT_EQ(sized.status, 0) << sized.output;
    const Png png = load_png(fs::path(out) / "images" / "00002.png");
    EXPECT_EQ(png.width, 2 * width) << "two panels side by side";
    EXPECT_EQ(png.height, height);
  }
}

TEST_F(RenderCli, BackendsListOrdersThePanels) {
  if (!run("--frames --render")) GTEST_SKIP() << skip_;
  const Outcome swapped = chainmail("render " + path("run") +
                                    " --backends massspring,plausible --out " + path("swapped"));
  ASSERT_EQ(swapped.status, 0) << swapped.output;
  // one camera frames both panels either way, so each panel moves over unchanged
  const Png original = load_png(dir_ / "run" / "images" / "00002.png");
  const Png turned = load_png(dir_ / "swapped" / "images" / "00002.png");
  ASSERT_EQ(original.width, turned.width);
  const size_t half = static_cast<size_t>(original.width / 2) * 4;
  for (int y = 0; y < original.height; ++y) {
    const unsigned char* a = &original.rgba[y * half * 2];
    const unsigned char* b = &turned.rgba[y * half * 2];
    ASSERT_EQ(0, std::memcmp(a, b + half, half)) << "row " << y;
    ASSERT_EQ(0, std::memcmp(a + half, b, half)) << "row " << y;
  }
  const Outcome one =
      chainmail("render " + path("run") + " --backends plausible --out " + path("one"));
  ASSERT_EQ(one.status, 0) << one.output;
  EXPECT_EQ(load_png(dir_ / "one" / "images" / "00000.png").width, original.width / 2);
}

TEST_F(RenderCli, BadInputIsOneLineExitTwoAndWritesNothing) {
  if (!run("--frames")) GTEST_SKIP() << skip_;
  for (const char* flags :
       {"--size 8x8", "--size wide", "--camera 1,2,3", "--camera 0,0,1:0,0,0:180", "--backends ode",
        "--backends plausible,", "--fps 30", "--export obj", "--no-images", "--samples 99",
        "--material unobtainium"}) {
    const Outcome bad = chainmail("render " + path("run") + " " + flags + " --out " + path("bad"));
    EXPECT_EQ(bad.status, 2) << flags << ": " << bad.output;
    EXPECT_EQ(std::count(bad.output.begin(), bad.output.end(), '\n'), 1) << bad.output;
    EXPECT_FALSE(fs::exists(path("bad"))) << flags;
  }
  // a folder that is not a run, and a run without saved frames
  EXPECT_EQ(chainmail("render " + path("missing")).status, 2);
  ASSERT_EQ(
      chainmail("run " + scene() + " --quiet --reference none --cache none --out " + path("bare"))
          .status,
      0);
  const Outcome bare = chainmail("render " + path("bare") + " --out " + path("bad"));
  EXPECT_EQ(bare.status, 2);
  EXPECT_NE(bare.output.find("--frames"), std::string::npos) << bare.output;
  // never into the run folder, nor into a folder of the user's
  const Outcome into_run = chainmail("render " + path("run") + " --out " + path("run"));
  EXPECT_EQ(into_run.status, 2) << into_run.output;
  EXPECT_TRUE(fs::exists(dir_ / "run" / "summary.json"));
  fs::create_directories(dir_ / "mine");
  std::ofstream(dir_ / "mine" / "notes.md") << "mine";
  EXPECT_EQ(chainmail("render " + path("run") + " --out " + path("mine")).status, 2);
  EXPECT_EQ(bytes_of(dir_ / "mine" / "notes.md"), "mine");
}

TEST_F(RenderCli, TheBenchsOneImageIsNamedForItsTime) {
  std::function<void(const SceneRun&, const std::string&)> writer;
  ::setenv("CHAINMAIL_SHADER_DIR", CHAINMAIL_SOURCE_DIR "/shaders", 0);  // none beside the tests
  try {
    writer = make_render_writer("", "", /*last_only=*/true);
  } catch (const SceneError& e) {
    GTEST_SKIP() << "no renderer here: " << e.what();
  }
  RunOptions options;
  options.backends = {"plausible"};
  options.progress = false;
  options.reference = "none";
  options.folder = path("bench");
  options.keep_stream = true;
  std::ifstream in(scene());
  const SceneRun run = run_scene(scene_from_json(json::parse(in), "scene.json"), options);
  writer(run, path("bench") + "/images");
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(path("bench") + "/images"))
    names.push_back(entry.path().filename().string());
  // the last sample: 13 steps of 4 ms (0.05 s rounded to whole steps)
  ASSERT_NEAR(run.runs[0].last->t, 0.052, 1e-12);
  EXPECT_EQ(names, std::vector<std::string>{"t0.052s.png"});
}

TEST_F(RenderCli, ExportOfA16x16CurtainHasOneInstancedMeshWithAnInstancePerRing) {
  const std::string curtain = std::string(CHAINMAIL_SOURCE_DIR) + "/bench/scenes/curtain.json";
  const Outcome run = chainmail("run " + curtain +
                                " --backends plausible --reference none --cache none --quiet "
                                "--set weave.rows=16 --set weave.cols=16 --set duration=0.1 "
                                "--export gltf --export npz --out " +
                                path("curtain"));
  ASSERT_EQ(run.status, 0) << run.output;
  const test::Glb glb = test::read_glb(path("curtain") + "/export/plausible.glb");
  ASSERT_TRUE(glb.doc.is_object());
  EXPECT_EQ(glb.doc["meshes"].size(), 1u);
  const int node = test::instanced_node(glb);
  ASSERT_GE(node, 0);
  const int translation =
      glb.doc["nodes"][node]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["TRANSLATION"];
  EXPECT_EQ(glb.doc["accessors"][translation]["count"], 256);
  EXPECT_EQ(glb.doc["animations"][0]["channels"].size(), 2u * 256);
  EXPECT_TRUE(fs::exists(path("curtain") + "/export/plausible.npz"));
  // the same from the saved frames, without drawing: render --no-images --export
  ASSERT_EQ(chainmail("run " + curtain +
                      " --backends plausible --reference none --cache none --quiet --frames "
                      "--set weave.rows=16 --set weave.cols=16 --set duration=0.1 --out " +
                      path("saved"))
                .status,
            0);
  const Outcome exported =
      chainmail("render " + path("saved") + " --no-images --export gltf --out " + path("exported"));
  ASSERT_EQ(exported.status, 0) << exported.output;
  EXPECT_FALSE(fs::exists(path("exported") + "/images"));
  const test::Glb again = test::read_glb(path("exported") + "/export/plausible.glb");
  EXPECT_EQ(again.doc["accessors"][translation]["count"], 256);
}

}  // namespace
}  // namespace chainmail
