// The checkered ground: no streaks where the plane lies on a tile boundary, and a checker that is
// filtered per pixel, so that one sample per pixel already looks like many.
#include <cmath>
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "core/scene.hpp"
#include "core/weave.hpp"
#include "render/renderer.hpp"
#include "test_scenes.hpp"

namespace chainmail::render {
namespace {

// a sheet hanging 2 cm above a ground plane at height `ground`, seen from a fixed camera low
// over the ground, so that the checker runs from large tiles in front to tiny ones far away
Scene ground_scene(double ground) {
  Scene scene = test::sheet_scene(12, 12);
  scene.weave.center = Vec3(0.0, ground + 0.02, 0.0);
  scene.weave.plane = SheetPlane::xz;
  return test::with_ground(
      test::with_camera(scene, Vec3(0.0, ground + 0.012, 0.06), Vec3(0.0, ground, -0.05)), ground);
}

RenderSettings settings(int width, int height, int samples) {
  RenderSettings s;
  s.width = width, s.height = height, s.samples = samples;
  s.labels = false;
  s.shader_dir = std::string(CHAINMAIL_SOURCE_DIR) + "/shaders";
  return s;
}

Image draw(const Scene& scene, const RenderSettings& s) {
  const Weave weave = make_weave(scene.weave, scene.ring);
  const RingFrame frame = test::rest_frame(weave);
  return Renderer::create(s)->render(scene, weave, {{"floor", &frame}});
}

// mean over the pixels of rows `first_row` on of |a - b|, in levels per channel (R, G, B)
double mean_difference(const Image& a, const Image& b, int first_row = 0, int end_row = -1) {
  if (end_row < 0) end_row = a.height;
  double sum = 0.0;
  const std::size_t first = static_cast<std::size_t>(first_row) * a.width * 4,
                    end = static_cast<std::size_t>(end_row) * a.width * 4;
  for (std::size_t i = first; i < end; i += 4) {
    for (int c = 0; c < 3; ++c) sum += std::abs(a.rgba[i + c] - b.rgba[i + c]);
  }
  return sum / (3.0 * a.width * (end_row - first_row));
}

// `big` box-filtered down by `factor` in each direction
Image downsample(const Image& big, int factor) {
  Image small;
  small.width = big.width / factor, small.height = big.height / factor;
  small.rgba.assign(static_cast<std::size_t>(small.width) * small.height * 4, 255);
  for (int y = 0; y < small.height; ++y) {
    for (int x = 0; x < small.width; ++x) {
      for (int c = 0; c < 3; ++c) {
        int sum = 0;
        for (int v = 0; v < factor; ++v) {
          for (int u = 0; u < factor; ++u) {
            sum +=
                big.rgba[((static_cast<std::size_t>(y) * factor + v) * big.width + x * factor + u) *
                             4 +
                         c];
          }
        }
        small.rgba[(static_cast<std::size_t>(y) * small.width + x) * 4 + c] =
            static_cast<unsigned char>((sum + factor * factor / 2) / (factor * factor));
      }
    }
  }
  return small;
}

TEST(RenderFloor, GroundOnATileBoundaryLooksLikeGroundBesideIt) {
  // tiles are n x tile apart from the world origin, so a plane at height 0 lies on a boundary of
  // any checker that also tiles the height: its pixels must not flip from tile to tile
  const Image on = draw(ground_scene(0.0), settings(320, 180, 4));
  const Image beside = draw(ground_scene(-1e-5), settings(320, 180, 4));
  EXPECT_LT(mean_difference(on, beside), 0.5);
}

TEST(RenderFloor, OneSamplePerPixelMatchesSixteenAveraged) {
  // the checker is box-filtered over each pixel in closed form: one sample per pixel and no
  // multisampling is close to the mean of 4 x 4 samples, also far away where tiles are smaller
  // than a pixel (where an unfiltered checker aliases into moire)
  const Scene scene = ground_scene(0.0);
  const Image one = draw(scene, settings(320, 180, 0));
  const Image sixteen = downsample(draw(scene, settings(1280, 720, 0)), 4);
  // the far ground just below the horizon, where tiles shrink below a pixel (the rings above
  // it alias without multisampling, which is not what is tested here; nearer tiles are easy)
  const double error = mean_difference(one, sixteen, one.height * 45 / 100, one.height * 55 / 100);
  EXPECT_LT(error, 0.4);  // the checker faded to its mean only past a pixel: 0.95
}

}  // namespace
}  // namespace chainmail::render
