#version 330 core
#include "env.glsl"
// simple shading: ambient + Lambert key light, a faint checker on the ground for scale
in vec3 v_world;
in vec3 v_normal;
in vec4 v_color;
out vec4 frag_color;
uniform vec3 u_eye;
uniform vec3 u_light_dir;
uniform vec3 u_origin;       // world position of the render origin (checker stays put)
uniform float u_checker;     // checker tile size, m
void main() {
  vec3 n = normalize(v_normal);
  if (dot(n, u_eye - v_world) < 0.0) n = -n;
  vec3 albedo = v_color.rgb;
  if (v_color.a > 0.5) {
    // fade the checker to its mean where tiles get smaller than a pixel (no moire far away)
    vec3 q = (v_world + u_origin) / u_checker;
    vec3 cell = floor(q);
    float tile = mod(cell.x + cell.y + cell.z, 2.0) < 0.5 ? 1.0 : 0.85;
    vec3 footprint = fwidth(q);
    float sharp = clamp(1.5 - 2.0 * max(footprint.x, max(footprint.y, footprint.z)), 0.0, 1.0);
    albedo *= mix(0.925, tile, sharp);
  }
  float diffuse = max(dot(n, u_light_dir), 0.0);
  frag_color = vec4(tone_map(albedo * (0.35 + 0.75 * diffuse)), 1.0);
}
