#version 330 core
#include "quaternion.glsl"
// one torus mesh per level of detail, instanced: every ring is the same mesh moved by its own
// centre and quaternion (local ring frame: ring in the X/Z plane, axis +Y)
layout(location = 0) in vec3 a_position;  // local, m
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec3 i_center;    // world, relative to the render origin
layout(location = 3) in vec4 i_rotation;  // unit quaternion (x, y, z, w), local -> world
uniform mat4 u_view_projection;
out vec3 v_world;
out vec3 v_normal;

void main() {
  v_world = i_center + rotate(i_rotation, a_position);
  v_normal = rotate(i_rotation, a_normal);
  gl_Position = u_view_projection * vec4(v_world, 1.0);
}
