// CPU side of the renderer: meshes (torus levels of detail, collider shapes, the cloth mesh), the
// camera and the per-ring level-of-detail choice. No GL here, so all of it is testable without a
// context.
#pragma once

#include <array>
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

// levels of detail, finest first: torus meshes (segments around the ring, around the wire) for
// rings big on screen, then a last level that draws each ring's bounding box and ray-casts the
// exact torus in it. On llvmpipe the ray-cast level is cheaper than any mesh under multisampling
// (whose cost grows with the number of small triangles) and its silhouette is exact; the meshes
// stay for close-ups, where its one-ball approximation of the first hit would show.
inline constexpr int kLodLevels = 3;
inline constexpr int kMeshLevels = kLodLevels - 1;
inline constexpr std::array<std::array<int, 2>, kMeshLevels> kLodSegments = {{{40, 14}, {24, 10}}};
// smallest on-screen ring diameter (pixels) for each level; below the last: ray-cast
inline constexpr std::array<double, kLodLevels - 1> kLodMinPixels = {192.0, 96.0};

// the unit box [-1, 1]^3 (stride 6: position, outward face normal), counter-clockwise outside
Mesh box_mesh();

int lod_for_pixels(double diameter_pixels);

struct CameraView {
  Eigen::Vector3d eye, target, up;  // world, m
  double fov_y_rad = 0.7;
  double aspect = 16.0 / 9.0;
  double near_plane = 0.01, far_plane = 10.0;
  Eigen::Vector3d forward() const { return (target - eye).normalized(); }
  Eigen::Vector3d right() const { return forward().cross(up).normalized(); }
  Eigen::Vector3d true_up() const { return right().cross(forward()); }
  // pixels per metre at unit depth for an image `height` pixels tall
  double focal_pixels(int height) const;
  // view and projection relative to `origin` (world positions are shifted by -origin in float)
  Eigen::Matrix4f view_projection(const Eigen::Vector3d& origin) const;
};

// finite ring centres of all frames, as an axis-aligned box (empty box when none)
struct Bounds {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(1e300);
  Eigen::Vector3d max = Eigen::Vector3d::Constant(-1e300);
  bool empty() const { return min.x() > max.x(); }
  Eigen::Vector3d center() const { return 0.5 * (min + max); }
  double radius() const { return empty() ? 0.0 : 0.5 * (max - min).norm(); }
  void add(const Eigen::Vector3d& p);
};
Bounds frame_bounds(const std::vector<const RingFrame*>& frames);

// the scene's camera, or (scene.camera.automatic) one that frames `bounds` from slightly above
// and in front; near and far planes from the bounds either way
CameraView make_camera(const Scene& scene, const Bounds& bounds, double aspect);

// the cloth path's mesh: ring centres joined into quads over the weave grid, per-vertex normals,
// uv = grid (i, j); each quad split into subdivisions^2 quads (bilinear) for displacement.
// Positions are relative to `origin`. Stride 8: position, normal, uv.
Mesh cloth_mesh(const RingFrame& frame, const Weave& weave, int subdivisions,
                const Eigen::Vector3d& origin);

// colliders, support and ground as world meshes relative to `origin`; stride 10: position,
// normal, rgba (a = 1: checkered). `extent` sizes the infinite planes.
Mesh scene_mesh(const Scene& scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& focus,
                double extent);

}  // namespace chainmail::render
