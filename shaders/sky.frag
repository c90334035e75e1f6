#version 330 core
#include "env.glsl"
// the skybox: the view ray through this pixel looks up the sharp environment
in vec2 v_ndc;
out vec4 frag_color;
uniform samplerCube u_env;
uniform mat3 u_ray_basis;  // columns: right * tan(fov_x / 2), up * tan(fov_y / 2), forward
void main() {
  vec3 ray = u_ray_basis * vec3(v_ndc, 1.0);
  frag_color = vec4(tone_map(texture(u_env, ray).rgb), 1.0);
}
