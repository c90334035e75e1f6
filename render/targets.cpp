#include "render/targets.hpp"

#include <algorithm>

namespace chainmail::render {
namespace {

// a framebuffer with a colour and a depth renderbuffer of `samples` samples (0: single-sampled)
void make_target(const GlApi& gl, int width, int height, int samples, GLuint& fbo, GLuint& color,
                 GLuint& depth) {
  gl.GenFramebuffers(1, &fbo);
  gl.GenRenderbuffers(1, &color);
  gl.GenRenderbuffers(1, &depth);
  gl.BindRenderbuffer(GL_RENDERBUFFER, color);
  if (samples > 0) {
    gl.RenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, width, height);
  } else {
    gl.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  }
  gl.BindRenderbuffer(GL_RENDERBUFFER, depth);
  if (samples > 0) {
    gl.RenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, width,
                                      height);
  } else {
    gl.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
  }
  gl.BindFramebuffer(GL_FRAMEBUFFER, fbo);
  gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
  gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
}

}  // namespace

PanelTargets make_panel_targets(const GlApi& gl, int width, int height, int samples) {
  PanelTargets t;
  t.width = width, t.height = height;
  GLint max_samples = 1;
  gl.GetIntegerv(GL_MAX_SAMPLES, &max_samples);
  t.samples = std::clamp(samples, 1, std::max(max_samples, 1));
  make_target(gl, width, height, 0, t.resolve_fbo, t.resolve_color, t.resolve_depth);
  check_framebuffer(gl, "the resolve target");
  if (t.samples > 1) {
    make_target(gl, width, height, t.samples, t.msaa_fbo, t.msaa_color, t.msaa_depth);
    check_framebuffer(gl, "the multisampled target");
  }
  check_gl(gl, "creating framebuffers");
  return t;
}

void delete_panel_targets(const GlApi& gl, const PanelTargets& t) {
  const GLuint framebuffers[] = {t.msaa_fbo, t.resolve_fbo};
  gl.DeleteFramebuffers(2, framebuffers);
  const GLuint renderbuffers[] = {t.msaa_color, t.msaa_depth, t.resolve_color, t.resolve_depth};
  gl.DeleteRenderbuffers(4, renderbuffers);
}

void resolve_samples(const GlApi& gl, const PanelTargets& t, bool with_depth) {
  if (t.samples <= 1) return;
  const int w = t.width, h = t.height;
  gl.BindFramebuffer(GL_READ_FRAMEBUFFER, t.msaa_fbo);
  gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, t.resolve_fbo);
  gl.BlitFramebuffer(0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  if (with_depth) gl.BlitFramebuffer(0, 0, w, h, 0, 0, w, h, GL_DEPTH_BUFFER_BIT, GL_NEAREST);
}

Image read_panel(const GlApi& gl, const PanelTargets& t, std::vector<unsigned char>& scratch) {
  const int w = t.width, h = t.height;
  gl.BindFramebuffer(GL_READ_FRAMEBUFFER, t.resolve_fbo);
  gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
  Image image;
  image.width = w, image.height = h;
  image.rgba.resize(static_cast<size_t>(w) * h * 4);
  scratch.resize(image.rgba.size());
  gl.ReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, scratch.data());
  check_gl(gl, "drawing a panel");
  const size_t row = static_cast<size_t>(w) * 4;
  for (int y = 0; y < h; ++y) {
    std::copy_n(&scratch[(h - 1 - y) * row], row, &image.rgba[y * row]);
  }
  return image;
}

}  // namespace chainmail::render
