// The procedural environment without a GL context: where the sun is, sky above ground, and the
// cubemap faces looking where GL expects them to.
#include <gtest/gtest.h>

#include "render/sky.hpp"

namespace chainmail::render {
namespace {

using Eigen::Vector3d;

double luminance(const Eigen::Vector3f& c) {
  return 0.2126 * c.x() + 0.7152 * c.y() + 0.0722 * c.z();
}

TEST(RenderSky, SunIsBrightestSkyIsBlueGroundIsDark) {
  const double sun = luminance(sky_color(sun_direction()));
  EXPECT_GT(sun, 20.0);  // the disk is HDR, far above white
  EXPECT_GT(sun, 10.0 * luminance(sky_color(-sun_direction())));
  const Eigen::Vector3f zenith = sky_color(Vector3d::UnitY() * 3.0);  // any length
  EXPECT_GT(zenith.z(), zenith.x());                                  // blue overhead
  EXPECT_LT(luminance(sky_color(-Vector3d::UnitY())), 0.5 * luminance(zenith) + 0.2);
  EXPECT_LT(luminance(sky_color(-Vector3d::UnitY())), luminance(sky_color(Vector3d(1, 0.3, 0))));
}

TEST(RenderSky, CubeFacesLookAlongTheirAxes) {
  const Vector3d axes[6] = {Vector3d::UnitX(),  -Vector3d::UnitX(), Vector3d::UnitY(),
                            -Vector3d::UnitY(), Vector3d::UnitZ(),  -Vector3d::UnitZ()};
  for (int face = 0; face < 6; ++face) {
    EXPECT_EQ(cube_direction(face, 0.0, 0.0), axes[face]) << face;
    // every texel direction of the face has that axis as its largest component
    for (double a : {-0.99, 0.0, 0.99}) {
      for (double b : {-0.99, 0.5, 0.99}) {
        const Vector3d d = cube_direction(face, a, b);
        EXPECT_DOUBLE_EQ(d.dot(axes[face]), 1.0);
        EXPECT_LE(d.cwiseAbs().maxCoeff(), 1.0);
      }
    }
  }
  // GL's layout: on +Z the face's s runs along +X and t along -Y
  EXPECT_EQ(cube_direction(4, 0.5, 0.25), Vector3d(0.5, -0.25, 1.0));
}

TEST(RenderSky, FaceTexelsAreTheSkyAtTheirCentres) {
  const int size = 8;
  const std::vector<float> face = sky_face(2, size);  // +Y, looking up
  ASSERT_EQ(face.size(), static_cast<size_t>(size * size * 4));
  for (int t = 0; t < size; ++t) {
    for (int s = 0; s < size; ++s) {
      const float* p = &face[(t * size + s) * 4];
      const Eigen::Vector3f expected =
          sky_color(cube_direction(2, (s + 0.5) / size * 2.0 - 1.0, (t + 0.5) / size * 2.0 - 1.0));
      EXPECT_EQ(Eigen::Vector3f(p[0], p[1], p[2]), expected) << s << "," << t;
      EXPECT_EQ(p[3], 1.0f);
    }
  }
}

}  // namespace
}  // namespace chainmail::render
