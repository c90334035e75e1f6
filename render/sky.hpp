// The procedural environment: a sky gradient with a sun, a hazy horizon with a line of hills and a
// darker ground, baked once into a cubemap, and a blurred copy of it for rough reflections.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "render/gl.hpp"

namespace chainmail::render {

// the sun's direction, which is also the key light (unit, world)
Eigen::Vector3d sun_direction();
inline constexpr int kSkyFaceSize = 256;      // texels per cubemap face side, sharp sky
inline constexpr int kBlurredFaceSize = 128;  // texels per face side, blurred copy
inline constexpr float kBlurSpread = 0.018f;  // blur tap spacing, radians

// linear HDR radiance of the sky seen along `direction` (any length)
Eigen::Vector3f sky_color(const Eigen::Vector3d& direction);

// direction of texel (a, b) in [-1, 1] on cubemap face 0..5 (+X, -X, +Y, -Y, +Z, -Z)
Eigen::Vector3d cube_direction(int face, double a, double b);

// one face of the sharp sky: size * size texels of RGBA floats (alpha 1), row by row
std::vector<float> sky_face(int face, int size);

struct SkyTextures {
  GLuint sharp = 0;    // cubemap, kSkyFaceSize, RGBA16F
  GLuint blurred = 0;  // cubemap, kBlurredFaceSize, prefiltered by `prefilter_program`
};

// both cubemaps; `prefilter_program` is prefilter.frag, drawn with the attribute-less `empty_vao`.
// Leaves the viewport and framebuffer binding changed; throws RenderError on a GL error
SkyTextures make_sky_textures(const GlApi& gl, GLuint prefilter_program, GLuint empty_vao);

}  // namespace chainmail::render
