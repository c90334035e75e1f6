#version 330 core
#include "env.glsl"
// renders one face of the blurred environment once at start-up, so that the ring shader can do
// the paper's 13-tap-per-axis blur with a single lookup per fragment
out vec4 frag_color;
uniform samplerCube u_env;
uniform int u_face;      // 0..5 = +X, -X, +Y, -Y, +Z, -Z
uniform float u_size;    // face size in texels
uniform float u_spread;  // blur tap spacing
void main() {
  vec2 st = gl_FragCoord.xy / u_size * 2.0 - 1.0;  // (s, t) in [-1, 1], GL cubemap convention
  float a = st.x, b = st.y;
  vec3 dir;
  if (u_face == 0) dir = vec3(1.0, -b, -a);
  else if (u_face == 1) dir = vec3(-1.0, -b, a);
  else if (u_face == 2) dir = vec3(a, 1.0, b);
  else if (u_face == 3) dir = vec3(a, -1.0, -b);
  else if (u_face == 4) dir = vec3(a, -b, 1.0);
  else dir = vec3(-a, -b, -1.0);
  frag_color = vec4(blurred_environment(u_env, dir, u_spread), 1.0);
}
