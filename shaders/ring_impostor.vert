#version 330 core
#include "quaternion.glsl"
// the farthest level of detail: instead of a torus mesh, each ring draws its bounding box (12
// triangles) and ring_impostor.frag ray-casts the exact torus inside it. Local ring frame as in
// ring.vert: ring in the X/Z plane, axis +Y.
layout(location = 0) in vec3 a_position;  // box corner, each coordinate -1 or +1
layout(location = 2) in vec3 i_center;    // world, relative to the render origin
layout(location = 3) in vec4 i_rotation;  // unit quaternion (x, y, z, w), local -> world
uniform mat4 u_view_projection;
uniform vec3 u_eye;           // relative to the render origin
uniform vec2 u_torus;         // wire radius a, centre radius c; m
uniform float u_pixel_angle;  // size of one pixel at unit distance (1 / focal length in pixels)
out vec3 v_local;             // this box point in the ring frame
flat out vec3 v_eye_local;    // the eye in the ring frame
flat out vec3 v_half;         // the box's half extents, m
flat out vec3 v_center;
flat out vec4 v_rotation;

void main() {
  // one pixel of margin so that the antialiased fringe around the wire is inside the box
  float margin = u_pixel_angle * distance(u_eye, i_center);
  v_half = vec3(u_torus.y + u_torus.x, u_torus.x, u_torus.y + u_torus.x) + margin;
  v_local = a_position * v_half;
  v_eye_local = rotate(vec4(-i_rotation.xyz, i_rotation.w), u_eye - i_center);
  v_center = i_center;
  v_rotation = i_rotation;
  gl_Position = u_view_projection * vec4(i_center + rotate(i_rotation, v_local), 1.0);
}
