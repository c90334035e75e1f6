// shared by the ring mesh and the ring ray-casting shaders, so that every level of detail is lit
// alike: the paper's ring material, the view ray reflected into the blurred skybox, tinted by the
// material colour, plus a Blinn-Phong key light from the sun's direction
#include "env.glsl"
uniform vec3 u_eye;
uniform vec3 u_light_dir;   // towards the sun, unit
uniform vec3 u_material;    // metal colour
uniform samplerCube u_env;          // sharp environment (live blur)
uniform samplerCube u_env_blurred;  // prefiltered with the same blur at start-up
// LIVE_BLUR (defined by the renderer on request): blur per fragment instead
uniform float u_spread;

// display colour of the wire at `world` with unit surface normal `n`
vec3 ring_color(vec3 world, vec3 n) {
  vec3 v = normalize(u_eye - world);
  if (dot(n, v) < 0.0) n = -n;  // silhouettes of thin wires at grazing angles
  vec3 r = reflect(-v, n);
#ifdef LIVE_BLUR
  vec3 env = blurred_environment(u_env, r, u_spread);
#else
  vec3 env = texture(u_env_blurred, r).rgb;
#endif
  vec3 h = normalize(u_light_dir + v);
  float diffuse = max(dot(n, u_light_dir), 0.0);
  float specular = pow(max(dot(n, h), 0.0), 80.0);
  vec3 color = u_material * (0.06 + 0.22 * diffuse) + u_material * env * 0.9 +
               specular * mix(vec3(1.0), u_material, 0.4) * 0.9;
  return tone_map(color);
}
