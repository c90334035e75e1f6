#include "render/sky.hpp"

#include <algorithm>
#include <cmath>

namespace chainmail::render {
namespace {

using Eigen::Vector3d;
using Eigen::Vector3f;

void set_cube_sampling(const GlApi& gl) {
  gl.TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  gl.TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  gl.TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl.TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  gl.TexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
}

// the sharp cubemap, uploaded face by face from sky_color()
GLuint make_sharp_cubemap(const GlApi& gl) {
  GLuint texture = 0;
  gl.GenTextures(1, &texture);
  gl.BindTexture(GL_TEXTURE_CUBE_MAP, texture);
  for (int f = 0; f < 6; ++f) {
    const std::vector<float> face = sky_face(f, kSkyFaceSize);
    gl.TexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f, 0, GL_RGBA16F, kSkyFaceSize, kSkyFaceSize, 0,
                  GL_RGBA, GL_FLOAT, face.data());
  }
  set_cube_sampling(gl);
  return texture;
}

// an empty cubemap for the blurred copy
GLuint make_blurred_cubemap(const GlApi& gl) {
  GLuint texture = 0;
  gl.GenTextures(1, &texture);
  gl.BindTexture(GL_TEXTURE_CUBE_MAP, texture);
  for (int f = 0; f < 6; ++f) {
    gl.TexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f, 0, GL_RGBA16F, kBlurredFaceSize,
                  kBlurredFaceSize, 0, GL_RGBA, GL_FLOAT, nullptr);
  }
  set_cube_sampling(gl);
  return texture;
}

// renders the blurred copy of `sky` into `blurred` once, face by face, with prefilter.frag
void prefilter(const GlApi& gl, GLuint program, GLuint empty_vao, GLuint sky, GLuint blurred) {
  GLuint fbo = 0;
  gl.GenFramebuffers(1, &fbo);
  gl.BindFramebuffer(GL_FRAMEBUFFER, fbo);
  gl.Viewport(0, 0, kBlurredFaceSize, kBlurredFaceSize);
  gl.Disable(GL_DEPTH_TEST);
  gl.UseProgram(program);
  gl.ActiveTexture(GL_TEXTURE0);
  gl.BindTexture(GL_TEXTURE_CUBE_MAP, sky);
  gl.Uniform1i(gl.GetUniformLocation(program, "u_env"), 0);
  gl.Uniform1f(gl.GetUniformLocation(program, "u_size"), static_cast<float>(kBlurredFaceSize));
  gl.Uniform1f(gl.GetUniformLocation(program, "u_spread"), kBlurSpread);
  gl.BindVertexArray(empty_vao);
  for (int f = 0; f < 6; ++f) {
    gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                            GL_TEXTURE_CUBE_MAP_POSITIVE_X + f, blurred, 0);
    check_framebuffer(gl, "the environment prefilter");
    gl.Uniform1i(gl.GetUniformLocation(program, "u_face"), f);
    gl.DrawArrays(GL_TRIANGLES, 0, 3);
  }
  gl.Finish();
  gl.DeleteFramebuffers(1, &fbo);
}

}  // namespace

Vector3d sun_direction() {
  static const Vector3d direction = Vector3d(0.45, 0.75, 0.5).normalized();
  return direction;
}

// sky gradient, sun, hazy horizon with a line of hills, darker ground; linear HDR values
Vector3f sky_color(const Vector3d& direction) {
  const Vector3d d = direction.normalized();
  const double e = d.y();
  const double azimuth = std::atan2(d.z(), d.x());
  const Vector3d horizon(0.80, 0.84, 0.88), zenith(0.20, 0.40, 0.78);
  const Vector3d ground_near(0.42, 0.39, 0.35), ground_far(0.18, 0.16, 0.14);
  Vector3d c;
  if (e >= 0.0) {
    c = horizon + (zenith - horizon) * std::pow(e, 0.45);
  } else {
    c = ground_near + (ground_far - ground_near) * std::pow(-e, 0.4);
  }
  const double hills =
      0.035 + 0.025 * std::sin(3.0 * azimuth) + 0.012 * std::sin(7.0 * azimuth + 1.0);
  if (e >= 0.0 && e < hills) c = Vector3d(0.30, 0.34, 0.30);
  c += Vector3d(1.0, 0.95, 0.85) * 0.22 * std::exp(-std::abs(e) * 30.0);
  const double s = std::max(d.dot(sun_direction()), 0.0);
  c += Vector3d(1.0, 0.92, 0.75) * (0.35 * std::pow(s, 40.0) + 6.0 * std::pow(s, 900.0));
  if (s > std::cos(0.035)) c += Vector3d(20.0, 19.0, 17.0);
  return c.cast<float>();
}

Vector3d cube_direction(int face, double a, double b) {
  switch (face) {
    case 0:
      return {1.0, -b, -a};
    case 1:
      return {-1.0, -b, a};
    case 2:
      return {a, 1.0, b};
    case 3:
      return {a, -1.0, -b};
    case 4:
      return {a, -b, 1.0};
    default:
      return {-a, -b, -1.0};
  }
}

std::vector<float> sky_face(int face, int size) {
  std::vector<float> texels(static_cast<size_t>(size) * size * 4);
  for (int t = 0; t < size; ++t) {
    for (int s = 0; s < size; ++s) {
      const double a = (s + 0.5) / size * 2.0 - 1.0;
      const double b = (t + 0.5) / size * 2.0 - 1.0;
      const Vector3f c = sky_color(cube_direction(face, a, b));
      float* p = &texels[(static_cast<size_t>(t) * size + s) * 4];
      p[0] = c.x(), p[1] = c.y(), p[2] = c.z(), p[3] = 1.0f;
    }
  }
  return texels;
}

SkyTextures make_sky_textures(const GlApi& gl, GLuint prefilter_program, GLuint empty_vao) {
  SkyTextures textures;
  textures.sharp = make_sharp_cubemap(gl);
  textures.blurred = make_blurred_cubemap(gl);
  prefilter(gl, prefilter_program, empty_vao, textures.sharp, textures.blurred);
  check_gl(gl, "building the environment map");
  return textures;
}

}  // namespace chainmail::render
