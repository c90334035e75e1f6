// The framebuffers a panel is drawn into: a multisampled target (when more than one sample is
// asked for and the driver has them), resolved by a blit into the single-sampled target that the
// ray-cast rings are blended into and that is read back.
#pragma once

#include <vector>

#include "render/gl.hpp"
#include "render/types.hpp"

namespace chainmail::render {

struct PanelTargets {
  int width = 0, height = 0;  // pixels
  int samples = 1;            // of the multisampled target; 1: there is none
  GLuint msaa_fbo = 0, msaa_color = 0, msaa_depth = 0;
  GLuint resolve_fbo = 0, resolve_color = 0, resolve_depth = 0;
  // where meshes, ground and sky are drawn
  GLuint draw_fbo() const { return samples > 1 ? msaa_fbo : resolve_fbo; }
};

// `samples` is clamped to what the driver offers; throws RenderError on an incomplete target
PanelTargets make_panel_targets(const GlApi& gl, int width, int height, int samples);
void delete_panel_targets(const GlApi& gl, const PanelTargets& targets);

// copies the samples into the single-sampled target: colour, and depth when `with_depth` (the
// ray-cast rings are still to be depth-tested against it)
void resolve_samples(const GlApi& gl, const PanelTargets& targets, bool with_depth);

// the single-sampled colour as an image, row 0 at the top; `scratch` holds GL's bottom-up rows
Image read_panel(const GlApi& gl, const PanelTargets& targets, std::vector<unsigned char>& scratch);

}  // namespace chainmail::render
