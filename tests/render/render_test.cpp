// The shared renderer: images of the requested size, rings where rings are, the background through
// the hole, identical panels for identical frames, clear errors without shaders or without GL.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>

#include <gtest/gtest.h>

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

#include "core/scene.hpp"
#include "core/weave.hpp"
#include "render/renderer.hpp"
#include "test_scenes.hpp"
#include "test_temp.hpp"

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#endif

namespace chainmail::render {
namespace {

namespace fs = std::filesystem;

const std::string kShaderDir = std::string(CHAINMAIL_SOURCE_DIR) + "/shaders";

using test::rest_frame;

// a 4-in-1 sheet of rows x cols rings (wire 1.6 mm, inner diameter 8 mm) over a ground plane at
// height `ground`, framed by the automatic camera
Scene make_scene(int rows, int cols) {
  return test::with_ground(test::sheet_scene(rows, cols), -0.02);
}
// the same seen from `eye`, looking at the origin with a 40 degree field
Scene make_scene_seen_from(int rows, int cols, const Vec3& eye, double ground = -0.02) {
  return test::with_ground(test::with_camera(test::sheet_scene(rows, cols), eye, Vec3::Zero()),
                           ground);
}

// the weave's first ring alone at the origin, flat (axis +Y), and no rings at all
RingFrame flat_ring_at_origin(const Weave& weave) {
  RingFrame ring = rest_frame(weave);
  ring.position.col(0).setZero();
  ring.set_quat(0, Quat::Identity());
  return ring;
}
RingFrame no_rings() {
  RingFrame empty;
  empty.resize(0);
  return empty;
}

RenderSettings small_settings() {
  RenderSettings settings;
  settings.width = 160;
  settings.height = 120;
  settings.shader_dir = kShaderDir;
  return settings;
}

const unsigned char* pixel(const Image& image, int x, int y) {
  return &image.rgba[(static_cast<size_t>(y) * image.width + x) * 4];
}

// summed over R, G, B, between (x, y) in `a` and (x + shift, y) in `b`
int pixel_difference(const Image& a, const Image& b, int x, int y, int shift = 0) {
  int sum = 0;
  for (int c = 0; c < 3; ++c) sum += std::abs(pixel(a, x, y)[c] - pixel(b, x + shift, y)[c]);
  return sum;
}

// share of a panel's pixels where its fabric changes the picture by more than 30 levels (summed
// over R, G, B): the panel is drawn beside one without rings, which shares its camera (the
// automatic camera frames every panel's rings), and the two halves are compared
double fabric_coverage(Renderer& renderer, const Scene& scene, const Weave& weave,
                       const Panel& panel, int threshold = 30) {
  RingFrame empty;
  empty.resize(0);
  empty.t = panel.frame ? panel.frame->t : 0.0;  // the same label
  const Image pair = renderer.render(scene, weave, {panel, {panel.label, &empty, panel.as_cloth}});
  const int width = pair.width / 2;
  int covered = 0;
  for (int y = 0; y < pair.height; ++y) {
    for (int x = 0; x < width; ++x) {
      covered += pixel_difference(pair, pair, x, y, width) > threshold;
    }
  }
  return static_cast<double>(covered) / (width * pair.height);
}

// a fresh directory under the system temp dir, removed by the destructor
struct TempDir {
  fs::path path;
  TempDir() {
    path = chainmail::test_temp_root() /
           ("chainmail_render_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

TEST(Render, KnownFrameWritesPngOfRequestedSize) {
  const Scene scene = make_scene(6, 6);
  const Weave weave = make_weave(scene.weave, scene.ring);
  const RingFrame frame = rest_frame(weave);
  auto renderer = Renderer::create(small_settings());
  const Image image = renderer->render(scene, weave, {{"plausible", &frame}});
  ASSERT_EQ(image.width, 160);
  ASSERT_EQ(image.height, 120);
  EXPECT_EQ(renderer->last_stats().instances, 36);
  // the rings are in the picture: the automatic camera fills much of it with the sheet
  EXPECT_GT(fabric_coverage(*renderer, scene, weave, {"plausible", &frame}), 0.2);

  TempDir dir;
  const std::string path = (dir.path / "frame.png").string();
  write_png(image, path);
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  int width = 0, height = 0, channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &width, &height, &channels, 4);
  ASSERT_NE(data, nullptr);
  EXPECT_EQ(width, 160);
  EXPECT_EQ(height, 120);
  // the PNG holds what render() returned
  EXPECT_EQ(0, std::memcmp(data, image.rgba.data(), image.rgba.size()));
  stbi_image_free(data);

  // not a uniform picture: many distinct colours
  std::set<unsigned> colours;
  for (size_t i = 0; i < image.rgba.size(); i += 4) {
    colours.insert(image.rgba[i] << 16 | image.rgba[i + 1] << 8 | image.rgba[i + 2]);
  }
  EXPECT_GT(colours.size(), 200u);
}

TEST(Render, CloseUpShowsWireAndBackgroundThroughTheHole) {
  // one ring at the origin, its axis (+Y) pointing at a camera straight above it
  const Scene scene = make_scene_seen_from(1, 1, Vec3(0.0, 0.03, 0.0));
  const Weave weave = make_weave(scene.weave, scene.ring);
  const RingFrame ring = flat_ring_at_origin(weave), empty = no_rings();

  RenderSettings settings = small_settings();
  settings.labels = false;
  auto renderer = Renderer::create(settings);
  const Image with_ring = renderer->render(scene, weave, {{"ring", &ring}});
  const Image without = renderer->render(scene, weave, {{"ring", &empty}});

  // centre radius c = 4.8 mm at 30 mm with a 40 degree field: 26.4 px from the image centre
  const double focal = 60.0 / std::tan(20.0 * 3.141592653589793 / 180.0);
  const int wire = static_cast<int>(std::lround(scene.ring.centre_radius / 0.03 * focal));
  ASSERT_NEAR(wire, 26, 1);
  for (const auto& [x, y] :
       {std::pair{80 + wire, 60}, {80 - wire, 60}, {80, 60 + wire}, {80, 60 - wire}}) {
    EXPECT_GT(pixel_difference(with_ring, without, x, y), 30) << "wire at " << x << "," << y;
  }
  // inside the hole (inner radius c - a = 4 mm = 22 px) the background shows unchanged
  const int hole =
      static_cast<int>((scene.ring.centre_radius - scene.ring.wire_radius) / 0.03 * focal) - 3;
  for (int y = 60 - hole; y <= 60 + hole; ++y) {
    for (int x = 80 - hole; x <= 80 + hole; ++x) {
      if ((x - 80) * (x - 80) + (y - 60) * (y - 60) > hole * hole) continue;
      ASSERT_EQ(pixel_difference(with_ring, without, x, y), 0) << "hole at " << x << "," << y;
    }
  }
  // and well outside the ring nothing changed either
  EXPECT_EQ(pixel_difference(with_ring, without, 5, 5), 0);
}

TEST(Render, IdenticalFramesGiveIdenticalPanels) {
  const Scene scene = make_scene(5, 5);
  const Weave weave = make_weave(scene.weave, scene.ring);
  const RingFrame a = rest_frame(weave), b = rest_frame(weave);
  auto renderer = Renderer::create(small_settings());
  const Image image = renderer->render(scene, weave, {{"same", &a}, {"same", &b}});
  ASSERT_EQ(image.width, 320);
  ASSERT_EQ(image.height, 120);
  // the panels show the sheet (two blank panels would be identical too)
  EXPECT_GT(fabric_coverage(*renderer, scene, weave, {"same", &a}), 0.2);
  for (int y = 0; y < image.height; ++y) {
    ASSERT_EQ(0, std::memcmp(pixel(image, 0, y), pixel(image, 160, y), 160 * 4)) << "row " << y;
  }

  // and a frame that differs gives a panel that differs
  RingFrame moved = rest_frame(weave);
  moved.position.row(1).array() += 0.01;
  const Image other = renderer->render(scene, weave, {{"same", &a}, {"same", &moved}});
  int differing = 0;
  for (int y = 0; y < other.height; ++y) {
    for (int x = 0; x < 160; ++x) {
      differing += std::memcmp(pixel(other, x, y), pixel(other, x + 160, y), 4) != 0;
    }
  }
  EXPECT_GT(differing, 100);
}

TEST(Render, SameInputSameImage) {
  const Scene scene = make_scene(4, 4);
  const Weave weave = make_weave(scene.weave, scene.ring);
  const RingFrame frame = rest_frame(weave);
  auto renderer = Renderer::create(small_settings());
  const Image first = renderer->render(scene, weave, {{"x", &frame}});
  // a picture worth comparing: the sheet covers much of it (two blank images would be equal
  // too); the two-panel image drawn for that in between leaves nothing behind
  EXPECT_GT(fabric_coverage(*renderer, scene, weave, {"x", &frame}), 0.2);
  const Image second = renderer->render(scene, weave, {{"x", &frame}});
  EXPECT_EQ(first.rgba, second.rgba);
}

TEST(Render, LevelOfDetailFollowsScreenSize) {
  const Scene scene = make_scene(20, 20);
  const Weave weave = make_weave(scene.weave, scene.ring);
  const RingFrame frame = rest_frame(weave);
  RenderSettings settings = small_settings();
  settings.lod = false;
  auto full = Renderer::create(settings);
  full->render(scene, weave, {{"x", &frame}});
  EXPECT_EQ(full->last_stats().per_lod[0], 400);

  // 400 rings across 160 px: a few pixels each, so no ring gets the finest mesh
  settings.lod = true;
  auto lod = Renderer::create(settings);
  lod->render(scene, weave, {{"x", &frame}});
  const FrameStats& stats = lod->last_stats();
  EXPECT_EQ(stats.instances, 400);
  EXPECT_EQ(stats.per_lod[0], 0);
  EXPECT_EQ(stats.per_lod[kLodLevels - 1], 400);  // all ray-cast
}

// share of pixels where `a` and `b` disagree on whether the fabric covers them: covered means
// more than `threshold` (summed over R, G, B) away from the same view without fabric
double coverage_disagreement(const Image& a, const Image& b, const Image& background,
                             int threshold) {
  int disagree = 0, covered = 0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      const bool in_a = pixel_difference(a, background, x, y) > threshold;
      const bool in_b = pixel_difference(b, background, x, y) > threshold;
      disagree += in_a != in_b;
      covered += in_a || in_b;
    }
  }
  return covered == 0 ? 1.0 : static_cast<double>(disagree) / covered;
}

// (x, y) is away from silhouettes: its 3x3 neighbourhood is fabric in both images
bool interior_in_both(const Image& a, const Image& b, const Image& background, int x, int y) {
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      if (pixel_difference(a, background, x + dx, y + dy) <= 60 ||
          pixel_difference(b, background, x + dx, y + dy) <= 60) {
        return false;
      }
    }
  }
  return true;
}

TEST(Render, RayCastRingsMatchTheFinestMesh) {
  // a 4x4 sheet seen obliquely from close by, so rings are large and interlock on screen
  const Scene scene = make_scene_seen_from(4, 4, Vec3(0.02, 0.035, 0.045));
  const Weave weave = make_weave(scene.weave, scene.ring);
  const RingFrame frame = rest_frame(weave), empty = no_rings();
  RenderSettings settings = small_settings();
  settings.width = 320, settings.height = 240, settings.labels = false;
  settings.lod = false;  // every ring the finest mesh
  auto mesh = Renderer::create(settings);
  const Image meshed = mesh->render(scene, weave, {{"x", &frame}});
  const Image background = mesh->render(scene, weave, {{"x", &empty}});
  ASSERT_EQ(mesh->last_stats().per_lod[0], 0);
  settings.lod = true;
  settings.lod_scale = 0.0;  // every ring ray-cast
  auto raycast = Renderer::create(settings);
  const Image cast = raycast->render(scene, weave, {{"x", &frame}});
  ASSERT_EQ(raycast->last_stats().per_lod[kLodLevels - 1], 16);

  // the same pixels are wire: they differ on silhouettes only, by antialiasing (3.5% here; a wire
  // 20% too thick or thin would be 20%)
  EXPECT_LT(coverage_disagreement(meshed, cast, background, 60), 0.08);
  // and where both are wire they are lit alike, the same ring in front where rings cross (the
  // ray-cast depth): mean difference under 3 levels per channel (0.2 here)
  double sum = 0.0;
  int both = 0;
  for (int y = 1; y + 1 < cast.height; ++y) {
    for (int x = 1; x + 1 < cast.width; ++x) {
      if (!interior_in_both(meshed, cast, background, x, y)) continue;
      sum += pixel_difference(meshed, cast, x, y) / 3.0;
      ++both;
    }
  }
  ASSERT_GT(both, 2000);
  EXPECT_LT(sum / both, 3.0);
}

TEST(Render, RayCastDepthIsTheSurfaceDepth) {
  // a flat ring whose wire is cut by the ground 0.9 a above its centre line: seen from above only
  // a strip of the wire's crown (sqrt(1 - 0.81) of its width) rises through the ground. The
  // ray-cast ring must show that strip like the finest mesh does; depth from its bounding box
  // instead of from the surface would show the whole width of the wire.
  const double a = 0.0008;  // make_scene's wire radius
  const Scene scene = make_scene_seen_from(1, 1, Vec3(0.0, 0.03, 0.0), 0.9 * a);
  const Weave weave = make_weave(scene.weave, scene.ring);
  const RingFrame ring = flat_ring_at_origin(weave), empty = no_rings();
  RenderSettings settings = small_settings();
  settings.width = 320, settings.height = 240, settings.labels = false;
  settings.lod = false;
  auto mesh = Renderer::create(settings);
  const Image background = mesh->render(scene, weave, {{"x", &empty}});
  auto visible = [&](const Image& image) {
    int count = 0;
    for (int y = 0; y < image.height; ++y) {
      for (int x = 0; x < image.width; ++x) count += pixel_difference(image, background, x, y) > 30;
    }
    return count;
  };
  const int meshed = visible(mesh->render(scene, weave, {{"x", &ring}}));
  settings.lod = true;
  settings.lod_scale = 0.0;
  auto raycast = Renderer::create(settings);
  const int cast = visible(raycast->render(scene, weave, {{"x", &ring}}));
  ASSERT_EQ(raycast->last_stats().per_lod[kLodLevels - 1], 1);
  // the strip: 2 pi c long, 2 a sqrt(0.19) wide, at 330 px per 30 mm: about 1400 px (antialiased
  // edges add to it); the whole wire would be 2.3 times that
  EXPECT_GT(meshed, 1000);
  EXPECT_NEAR(cast, meshed, 0.25 * meshed) << "ray-cast " << cast << ", mesh " << meshed;
}

// mean over pixels of the squared change (levels of 255, summed over R, G, B) from one image to
// the next: a wire sliding across a pixel in small steps costs little when the pixel follows its
// coverage, and a lot when the pixel jumps between wire and background (shimmer)
double flicker_energy(const Image& a, const Image& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.rgba.size(); i += 4) {
    double change = 0.0;
    for (int c = 0; c < 3; ++c) change += std::abs(a.rgba[i + c] - b.rgba[i + c]);
    sum += change * change;
  }
  return sum / (a.rgba.size() / 4);
}

TEST(Render, ThinWiresDoNotShimmerUnderSubPixelMotion) {
  // a sheet filling the view from above: rings about 9 px across, wires about 1.3 px
  const Scene scene = make_scene_seen_from(40, 40, Vec3(0.0, 0.45, 0.001));
  const Weave weave = make_weave(scene.weave, scene.ring);
  const RingFrame frame = rest_frame(weave);
  RenderSettings settings = small_settings();
  settings.width = 320, settings.height = 240, settings.labels = false;
  // the sheet slides sideways by one pixel in eighths
  const double pixel_size = 0.45 * std::tan(20.0 * 3.141592653589793 / 180.0) / 120.0;
  auto flicker = [&](Renderer& renderer) {
    double energy = 0.0;
    Image previous = renderer.render(scene, weave, {{"x", &frame}});
    for (int k = 1; k <= 8; ++k) {
      RingFrame moved = frame;
      moved.position.row(0).array() += k * pixel_size / 8.0;
      Image image = renderer.render(scene, weave, {{"x", &moved}});
      energy += flicker_energy(previous, image);
      previous = std::move(image);
    }
    return energy;
  };

  // the control, without antialiasing: the finest mesh at one sample per pixel
  settings.samples = 1;
  settings.lod = false;
  auto aliased = Renderer::create(settings);
  const double aliased_flicker = flicker(*aliased);
  // the default path: rings this small are ray-cast with their coverage
  settings.samples = 4;
  settings.lod = true;
  auto antialiased = Renderer::create(settings);
  const double antialiased_flicker = flicker(*antialiased);
  ASSERT_GT(antialiased->last_stats().per_lod[kLodLevels - 1], 1000);
  EXPECT_LT(antialiased_flicker, 0.5 * aliased_flicker)
      << "antialiased " << antialiased_flicker << ", aliased " << aliased_flicker;
  // and it shimmers no more than the finest mesh under 4x multisampling
  settings.lod = false;
  auto multisampled = Renderer::create(settings);
  const double multisampled_flicker = flicker(*multisampled);
  EXPECT_LT(antialiased_flicker, 1.25 * multisampled_flicker)
      << "ray-cast " << antialiased_flicker << ", 4x MSAA mesh " << multisampled_flicker;
}

TEST(Render, ClothPathDrawsEveryShader) {
  const Scene scene = make_scene(6, 6);
  const Weave weave = make_weave(scene.weave, scene.ring);
  const RingFrame frame = rest_frame(weave);
  RenderSettings settings = small_settings();
  settings.labels = false;
  auto rings = Renderer::create(settings);
  const Image ring_image = rings->render(scene, weave, {{"x", &frame}});
  for (const std::string& name : cloth_shader_names()) {
    settings.cloth_shader = name;
    auto renderer = Renderer::create(settings);
    const Image cloth = renderer->render(scene, weave, {{"x", &frame, true}});
    EXPECT_NE(cloth.rgba, ring_image.rgba) << name;
    // the cloth is drawn: the quads between ring centres (an eighth of the view; the texture's
    // holes show the ground through half of that) differ from the ground beneath
    EXPECT_GT(fabric_coverage(*renderer, scene, weave, {"x", &frame, true}, 10), 0.03) << name;
  }
  settings.cloth_shader = "velvet";
  EXPECT_THROW(Renderer::create(settings), RenderError);
}

TEST(Render, MissingShaderFileIsAClearError) {
  TempDir dir;
  for (const auto& entry : fs::directory_iterator(kShaderDir)) {
    if (entry.path().filename() != "ring.frag") fs::copy(entry.path(), dir.path);
  }
  RenderSettings settings = small_settings();
  settings.shader_dir = dir.path.string();
  try {
    Renderer::create(settings);
    FAIL() << "a shader directory without ring.frag was accepted";
  } catch (const RenderError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("ring.frag"), std::string::npos) << message;
    EXPECT_NE(message.find(dir.path.string()), std::string::npos) << message;
    EXPECT_NE(message.find("missing shader file"), std::string::npos) << message;
  }
}

TEST(Render, NoGlAvailableIsAClearError) {
  // as on a machine with neither library: both loads fail, and auto says so
  RenderSettings settings = small_settings();
  settings.osmesa_library = "/nonexistent/libOSMesa.so.8";
  settings.egl_library = "/nonexistent/libEGL.so.1";
  try {
    Renderer::create(settings);
    FAIL() << "a renderer was created without any GL library";
  } catch (const RenderError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("no OpenGL available"), std::string::npos) << message;
    EXPECT_NE(message.find("OSMesa"), std::string::npos) << message;
    EXPECT_NE(message.find("EGL"), std::string::npos) << message;
  }
  settings = small_settings();
  settings.context = "vulkan";
  try {
    Renderer::create(settings);
    FAIL() << "an unknown context was accepted";
  } catch (const RenderError& error) {
    EXPECT_NE(std::string(error.what()).find("unknown GL context 'vulkan'"), std::string::npos);
  }
}

TEST(Render, OsmesaAndEglDrawTheSameImage) {
  const Scene scene = make_scene(5, 5);
  const Weave weave = make_weave(scene.weave, scene.ring);
  const RingFrame frame = rest_frame(weave);
  Image images[2];
  const char* kinds[2] = {"osmesa", "egl"};
  for (int k = 0; k < 2; ++k) {
#if defined(__SANITIZE_ADDRESS__)
    // Mesa's EGL driver keeps allocations and is unloaded at eglTerminate, so its frames cannot
    // be named in a suppression (render/gl.cpp): what it allocates here is not leak-checked
    __lsan::ScopedDisabler unchecked;
#endif
    RenderSettings settings = small_settings();
    settings.context = kinds[k];
    std::unique_ptr<Renderer> renderer;
    try {
      renderer = Renderer::create(settings);
    } catch (const RenderError& error) {
      GTEST_SKIP() << kinds[k] << " is not available here: " << error.what();
    }
    EXPECT_EQ(renderer->context_name(), kinds[k]);
    images[k] = renderer->render(scene, weave, {{"x", &frame}});
    EXPECT_GT(fabric_coverage(*renderer, scene, weave, {"x", &frame}), 0.2) << kinds[k];
  }
  EXPECT_EQ(images[0].rgba, images[1].rgba);
}

}  // namespace
}  // namespace chainmail::render
