// shared by the ring, cloth and prefilter shaders: the environment (skybox) lookups.
// The paper (sec. 5) roughens the reflection with a one-dimensional 13-tap Gaussian applied along
// every axis (the fast blur of DesLauriers 2015: 7 linear fetches give 13 taps). On a cubemap the
// "pixels" are directions, so the taps step the lookup direction along x, y and z in turn.

vec3 blur13_along(samplerCube env, vec3 dir, vec3 step_dir) {
  vec3 o1 = step_dir * 1.411764705882353;
  vec3 o2 = step_dir * 3.2941176470588234;
  vec3 o3 = step_dir * 5.176470588235294;
  vec3 color = texture(env, dir).rgb * 0.1964825501511404;
  color += (texture(env, dir + o1).rgb + texture(env, dir - o1).rgb) * 0.2969069646728344;
  color += (texture(env, dir + o2).rgb + texture(env, dir - o2).rgb) * 0.09447039785044732;
  color += (texture(env, dir + o3).rgb + texture(env, dir - o3).rgb) * 0.010381362401148057;
  return color;
}

// average of the three per-axis blurs; spread = tap spacing in direction units
vec3 blurred_environment(samplerCube env, vec3 dir, float spread) {
  dir = normalize(dir);
  return (blur13_along(env, dir, vec3(spread, 0.0, 0.0)) +
          blur13_along(env, dir, vec3(0.0, spread, 0.0)) +
          blur13_along(env, dir, vec3(0.0, 0.0, spread))) / 3.0;
}

// the display transform shared by every shader: soft shoulder instead of a hard clip
vec3 tone_map(vec3 color) {
  return vec3(1.0) - exp(-1.25 * color);
}
