// a procedural chainmail tile: one ring per (i, j) cell, drawn as a raised annulus. The cloth
// baseline stretches this texture with its triangles, which is exactly the artefact to show.
float ring_texture_height(vec2 uv) {
  vec2 p = fract(uv) - 0.5;
  float wire = (length(p) - 0.33) / 0.1;  // 0 on the wire's centre line, +-1 at its edges
  return sqrt(max(1.0 - wire * wire, 0.0));
}
