#version 330 core
#include "ring_shading.glsl"
// the torus meshes (the nearer levels of detail): the material at the interpolated normal
in vec3 v_world;
in vec3 v_normal;
out vec4 frag_color;

void main() {
  frag_color = vec4(ring_color(v_world, normalize(v_normal)), 1.0);
}
