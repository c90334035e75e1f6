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

// fraction of the dark tiles of a unit checker inside a pixel footprint `w` tiles wide around
// `p`: the checker box-filtered in closed form (the integral of a square wave is a triangle
// wave), so tiles smaller than a pixel blend to their mean instead of aliasing into moire
float filtered_checker(vec2 p, vec2 w) {
  w = max(w, vec2(1e-4));
  vec2 lo = abs(fract((p - 0.5 * w) * 0.5) - 0.5), hi = abs(fract((p + 0.5 * w) * 0.5) - 0.5);
  vec2 i = 2.0 * (lo - hi) / w;
  return 0.5 - 0.5 * i.x * i.y;
}

void main() {
  vec3 face = normalize(v_normal);  // as built: the checker must not flip with the side seen
  vec3 n = dot(face, u_eye - v_world) < 0.0 ? -face : face;
  vec3 albedo = v_color.rgb;
  if (v_color.a > 0.5) {
    // tiles in the plane's own two axes: a third axis across the plane would put the plane on a
    // tile boundary, where round-off flips the tile from pixel to pixel (streaks)
    vec3 t1 = normalize(cross(abs(face.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0), face));
    vec3 t2 = cross(face, t1);
    vec3 world = v_world + u_origin;
    vec2 q = vec2(dot(world, t1), dot(world, t2)) / u_checker;
    float dark = filtered_checker(q, max(abs(dFdx(q)), abs(dFdy(q))));
    albedo *= mix(1.0, 0.85, dark);
  }
  float diffuse = max(dot(n, u_light_dir), 0.0);
  frag_color = vec4(tone_map(albedo * (0.35 + 0.75 * diffuse)), 1.0);
}
