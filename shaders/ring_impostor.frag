#version 330 core
#include "ring_shading.glsl"
#include "quaternion.glsl"
// ray-cast torus for rings a few pixels wide. The torus is the union of balls of radius a centred
// on its centre circle, so the view ray hits it exactly where it passes within a of that circle.
// The circle point nearest the ray is found by alternating projections (ray -> circle -> ray),
// started where the ray crosses the ring's plane; the ball there gives the hit, its normal and
// its depth, and the ray's distance to the wire's surface gives the pixel's coverage (antialiased
// edges without tiny triangles).
in vec3 v_local;
flat in vec3 v_eye_local;
flat in vec3 v_half;
flat in vec3 v_center;
flat in vec4 v_rotation;
out vec4 frag_color;
uniform mat4 u_view_projection;
uniform vec2 u_torus;         // wire radius a, centre radius c; m
uniform float u_pixel_angle;  // size of one pixel at unit distance

const int kProjections = 3;

// the point of the centre circle (radius c in the ring plane) nearest to p
vec3 centre_circle_point(vec3 p) {
  return u_torus.y * normalize(vec3(p.x, 0.0, p.z) + vec3(1e-9, 0.0, 0.0));
}

void main() {
  float a = u_torus.x;  // wire radius
  vec3 origin = v_eye_local;
  vec3 dir = normalize(v_local - origin);
  // the ray's span inside the box
  float t_entry = dot(v_local - origin, dir);
  vec3 inv = 1.0 / dir;
  vec3 far_side = max((-v_half - origin) * inv, (v_half - origin) * inv);
  float t_exit = min(far_side.x, min(far_side.y, far_side.z));

  // start where the ray crosses the ring's plane (edge-on: where it enters the box)
  float t = -origin.y * inv.y;
  if (!(t >= t_entry && t <= t_exit)) t = t_entry;
  vec3 centre_point = vec3(0.0);
  for (int i = 0; i < kProjections; ++i) {
    vec3 p = origin + t * dir;
    centre_point = centre_circle_point(p);
    t = dot(centre_point - origin, dir);
  }
  vec3 nearest = origin + t * dir;
  float miss = length(nearest - centre_point);  // ray to centre circle
  float coverage = clamp(0.5 - (miss - a) / (u_pixel_angle * t), 0.0, 1.0);
  if (coverage <= 0.0) discard;

  // entry into the ball (on the silhouette when the ray misses it)
  vec3 p = nearest - dir * sqrt(max(a * a - miss * miss, 0.0));
  // the torus normal at p: away from the circle point under p (not the ball's centre)
  vec3 n = rotate(v_rotation, normalize(p - centre_circle_point(p)));
  vec3 world = v_center + rotate(v_rotation, p);
  vec4 clip = u_view_projection * vec4(world, 1.0);
  gl_FragDepth = 0.5 + 0.5 * clip.z / clip.w;
  frag_color = vec4(ring_color(world, n), coverage);
}
