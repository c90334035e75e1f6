// CPU side of the renderer's geometry: the torus and box meshes of the ring levels of detail,
// collider shapes and the cloth mesh. No GL here, so all of it is testable without a context.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/frame.hpp"
#include "core/scene.hpp"
#include "core/weave.hpp"

namespace chainmail::render {

// interleaved vertices: position (3), normal (3), then `extra` floats (uv or colour)
struct Mesh {
  int stride = 6;  // floats per vertex
  std::vector<float> vertices;
  std::vector<std::uint32_t> indices;  // triangles, counter-clockwise seen from outside
  int vertex_count() const { return static_cast<int>(vertices.size()) / stride; }
};

// torus in the local ring frame (ring in X/Z, axis +Y): u around the ring, v around the wire
Mesh torus_mesh(double wire_radius, double centre_radius, int segments_u, int segments_v);

// the unit box [-1, 1]^3 (stride 6: position, outward face normal), counter-clockwise outside
Mesh box_mesh();

// each ring's strain: the mean over its grid neighbours of distance / rest distance - 1 (0 for a
// ring with none); the cloth mesh carries it so that the shader can show where the sheet stretches
std::vector<double> ring_strain(const RingFrame& frame, const Weave& weave);

// the cloth path's mesh: ring centres joined into quads over the weave grid, per-vertex normals,
// uv = grid (i, j) and ring_strain; each quad split into subdivisions^2 quads (bilinear) for
// displacement. Positions are relative to `origin`. Stride 9: position, normal, uv, strain.
Mesh cloth_mesh(const RingFrame& frame, const Weave& weave, int subdivisions,
                const Eigen::Vector3d& origin);

// colliders, support and ground as world meshes relative to `origin`; stride 10: position,
// normal, rgba (a = 1: checkered). `extent` sizes the infinite planes.
Mesh scene_mesh(const Scene& scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& focus,
                double extent);

}  // namespace chainmail::render
