// What the renderer draws, worked out without GL: the camera that frames the fabric, which rings
// the view can see, each ring's level of detail from its size on screen, and the per-instance
// arrays (ring centre and orientation) that the instanced draws read. The GL side only uploads
// what this module packs, so all of it is testable without a context.
#pragma once

#include <array>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/frame.hpp"
#include "core/scene.hpp"

namespace chainmail::render {

// ---- levels of detail ---------------------------------------------------------------------------

// finest first: torus meshes (segments around the ring, around the wire) for rings big on screen,
// then a last level that draws each ring's bounding box and ray-casts the exact torus in it. On
// llvmpipe the ray-cast level is cheaper than any mesh under multisampling (whose cost grows with
// the number of small triangles) and its silhouette is exact; the meshes stay for close-ups, where
// its one-ball approximation of the first hit would show.
inline constexpr int kLodLevels = 3;
inline constexpr int kMeshLevels = kLodLevels - 1;
inline constexpr std::array<std::array<int, 2>, kMeshLevels> kLodSegments = {{{40, 14}, {24, 10}}};
// smallest on-screen ring diameter (pixels) for each level; below the last: ray-cast
inline constexpr std::array<double, kLodLevels - 1> kLodMinPixels = {192.0, 96.0};

// the level for a ring `diameter_pixels` across on screen
int lod_for_pixels(double diameter_pixels);

// ---- camera -------------------------------------------------------------------------------------

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

// where the automatic camera looks from (towards the eye): in front, about 30 degrees up
inline const Eigen::Vector3d kAutomaticViewFrom(0.0, 0.6, 1.0);

// the scene's camera, or (scene.camera.automatic, or `view_from` given) one that frames `bounds`
// from the direction `view_from` (default kAutomaticViewFrom) with the scene's field of view;
// near and far planes from the bounds either way
CameraView make_camera(const Scene& scene, const Bounds& bounds, double aspect,
                       const std::optional<Eigen::Vector3d>& view_from = std::nullopt);

// the full-screen sky's ray directions: columns right * tan(fov_x / 2), up * tan(fov_y / 2),
// forward, so that ndc (x, y, 1) maps to the world direction through that pixel
Eigen::Matrix3f sky_ray_basis(const CameraView& camera);

// what every panel of one image shares: one camera for all of them
struct SharedView {
  CameraView camera;
  Eigen::Vector3d origin;  // float positions are relative to this (the camera target), m
  Eigen::Vector3d focus;   // fabric centre (camera target when there are no rings), m
  double fabric_radius;    // padded by one ring, m
  float checker;           // ground checker tile: 1, 2 or 5 x 10^k up to fabric_radius / 2, m
};
SharedView shared_view(const Scene& scene, const std::vector<const RingFrame*>& frames,
                       double aspect,
                       const std::optional<Eigen::Vector3d>& view_from = std::nullopt);

// ---- culling and level of detail ----------------------------------------------------------------

// the view frustum widened by a ring's bounding-sphere radius, so that a ring is kept while any of
// it may be on screen
struct RingFrustum {
  Eigen::Vector3d eye, forward, right, up;  // world, m; unit axes
  double near_plane = 0, far_plane = 0;     // m along forward
  double tan_x = 0, tan_y = 0;              // half-angle tangents of the field of view
  double radius = 0;                        // ring bounding sphere, m
  double slack_x = 0, slack_y = 0;          // radius / cos(half-angle): the side planes' margin, m
};
RingFrustum ring_frustum(const CameraView& camera, double ring_radius);

// true when a ring centred at `p` may be seen; `depth` is its distance along the view axis, m
bool ring_visible(const RingFrustum& frustum, const Eigen::Vector3d& p, double& depth);

// the level of detail of a ring `depth` m in front of the camera
struct LodChoice {
  bool enabled = true;        // false: every ring the finest mesh
  double scale = 1.0;         // on-screen size is scaled by this before the level is picked
  double ring_radius = 0.0;   // m
  double focal_pixels = 1.0;  // pixels per metre at unit depth
  int level(double depth) const;
};

// ---- instance packing ---------------------------------------------------------------------------

inline constexpr int kInstanceFloats = 7;  // centre (3), quaternion x, y, z, w (4)

// a frame's quaternion column (w, x, y, z) as the shaders take it: unit length, (x, y, z, w)
Eigen::Vector4f shader_quaternion(const Eigen::Vector4d& wxyz);

// the rings of one panel, culled, sorted into levels of detail and packed for instanced drawing:
// the mesh levels front to back (cheaper fragments through the early depth test), the ray-cast
// level back to front (it is blended)
struct RingInstances {
  std::vector<float> data;                    // total() * kInstanceFloats, level by level
  std::array<int, kLodLevels + 1> offsets{};  // first instance of each level, then the end
  std::array<std::vector<std::pair<double, int>>, kLodLevels> buckets;  // (depth m, ring) scratch
  int count(int level) const { return offsets[level + 1] - offsets[level]; }
  int total() const { return offsets[kLodLevels]; }
};

// fills `out` (its storage is reused from frame to frame); positions are relative to `origin`.
// Rings with a non-finite centre or quaternion, or a zero quaternion, are dropped
void pack_ring_instances(const RingFrame& frame, const RingFrustum& frustum, const LodChoice& lod,
                         const Eigen::Vector3d& origin, RingInstances& out);

}  // namespace chainmail::render
