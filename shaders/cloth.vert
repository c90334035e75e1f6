#version 330 core
#include "cloth_texture.glsl"
// the cloth path: the frame's ring centres as a triangle mesh over the weave grid
layout(location = 0) in vec3 a_position;  // world, relative to the render origin
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;        // weave grid (i, j): one texture tile per ring
layout(location = 3) in float a_strain;   // mean neighbour distance / rest distance - 1
uniform mat4 u_view_projection;
uniform float u_displacement;  // m along the normal at full texture height (0: off)
out vec3 v_world;
out vec3 v_normal;
out vec2 v_uv;
out float v_strain;
void main() {
  vec3 n = normalize(a_normal);
  v_world = a_position + n * (u_displacement * ring_texture_height(a_uv));
  v_normal = n;
  v_uv = a_uv;
  v_strain = a_strain;
  gl_Position = u_view_projection * vec4(v_world, 1.0);
}
