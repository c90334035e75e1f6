#version 330 core
#include "env.glsl"
#include "cloth_texture.glsl"
// the cloth document's shaders, picked by u_mode:
// 0 blinn_phong, 1 texture, 2 bump, 3 displacement, 4 mirror
in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;
in float v_strain;
out vec4 frag_color;
uniform int u_mode;
uniform vec3 u_eye;
uniform vec3 u_light_dir;
uniform vec3 u_material;
uniform float u_bump;  // bump strength
uniform samplerCube u_env;

vec3 blinn_phong(vec3 albedo, vec3 n, vec3 v, float shininess) {
  vec3 h = normalize(u_light_dir + v);
  float diffuse = max(dot(n, u_light_dir), 0.0);
  float specular = pow(max(dot(n, h), 0.0), shininess);
  return albedo * (0.12 + 0.7 * diffuse) + vec3(0.5) * specular;
}

// the material tinted by the local strain, so that the picture shows where the cloth stretches
// (toward red, full at the 10 % over-extension limit) or is compressed (toward blue)
vec3 strained(vec3 base) {
  float s = clamp(v_strain / 0.1, -1.0, 1.0);
  return s > 0.0 ? mix(base, vec3(0.85, 0.12, 0.04), s) : mix(base, vec3(0.08, 0.25, 0.85), -s);
}

// the ring texture's colour: metal on the wire, dark in the gaps (which texture modes discard)
vec3 ring_albedo(float height) {
  return height > 0.0 ? strained(u_material) * (0.45 + 0.55 * height) : vec3(0.06);
}

// bump mapping from screen-space derivatives (no tangents needed)
vec3 bumped_normal(vec3 n, float height) {
  vec3 dpdx = dFdx(v_world), dpdy = dFdy(v_world);
  float dhdx = dFdx(height), dhdy = dFdy(height);
  vec3 r1 = cross(dpdy, n), r2 = cross(n, dpdx);
  float det = dot(dpdx, r1);
  vec3 gradient = sign(det) * (dhdx * r1 + dhdy * r2);
  return normalize(abs(det) * n - u_bump * gradient);
}

void main() {
  vec3 v = normalize(u_eye - v_world);
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;
  float height = ring_texture_height(v_uv);
  // the chainmail texture is alpha-tested, as textured mail is drawn in practice: the gaps between
  // the painted rings are holes through which the scene shows
  if ((u_mode == 1 || u_mode == 2) && height <= 0.0) discard;
  vec3 color;
  if (u_mode == 0) {
    color = blinn_phong(strained(u_material), n, v, 32.0);
  } else if (u_mode == 1) {
    color = blinn_phong(ring_albedo(height), n, v, 32.0);
  } else if (u_mode == 2) {
    color = blinn_phong(ring_albedo(height), bumped_normal(n, height), v, 48.0);
  } else if (u_mode == 3) {
    vec3 facet = normalize(cross(dFdx(v_world), dFdy(v_world)));
    if (dot(facet, v) < 0.0) facet = -facet;
    color = blinn_phong(ring_albedo(height), facet, v, 48.0);
  } else {
    color = u_material * texture(u_env, reflect(-v, n)).rgb;
  }
  frag_color = vec4(tone_map(color), 1.0);
}
