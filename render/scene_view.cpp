#include "render/scene_view.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

namespace chainmail::render {
namespace {

using Eigen::Vector3d;
constexpr double kPi = std::numbers::pi;

// the automatic camera: look at the box from `from` (towards the eye) and back off until every
// corner of the (ring-padded) box is inside the view with a margin: for a corner at (x, y) across
// and z towards the camera, depth d - z must reach |x| / tan(fov_x / 2) and |y| / tan(fov_y / 2)
void frame_automatically(CameraView& view, const Bounds& bounds, const Vector3d& center,
                         double radius, double ring_extent, const Vector3d& from) {
  const Vector3d to_eye = from.normalized();
  Vector3d across = Vector3d::UnitY().cross(to_eye);
  // straight down: image right is world +X (make_camera picks the matching up)
  across = across.norm() < 1e-9 ? Vector3d(Vector3d::UnitX()) : Vector3d(across.normalized());
  const Vector3d upward = to_eye.cross(across);
  const double margin = 0.92;
  const double tan_y = margin * std::tan(0.5 * view.fov_y_rad), tan_x = tan_y * view.aspect;
  double distance = radius;
  const Vector3d lo = bounds.empty() ? center : Vector3d(bounds.min),
                 hi = bounds.empty() ? center : Vector3d(bounds.max);
  for (int corner = 0; corner < 8; ++corner) {
    const Vector3d p((corner & 1 ? hi.x() : lo.x()) + (corner & 1 ? 1 : -1) * ring_extent,
                     (corner & 2 ? hi.y() : lo.y()) + (corner & 2 ? 1 : -1) * ring_extent,
                     (corner & 4 ? hi.z() : lo.z()) + (corner & 4 ? 1 : -1) * ring_extent);
    const Vector3d r = p - center;
    const double z = r.dot(to_eye);
    distance = std::max(
        {distance, z + std::abs(r.dot(across)) / tan_x, z + std::abs(r.dot(upward)) / tan_y});
  }
  view.target = center;
  view.eye = center + distance * to_eye;
}

// the largest of 1, 2, 5 x 10^k up to `limit`
double round_tile(double limit) {
  const double decade = std::pow(10.0, std::floor(std::log10(limit)));
  return decade * (limit >= 5 * decade ? 5.0 : limit >= 2 * decade ? 2.0 : 1.0);
}

}  // namespace

int lod_for_pixels(double diameter_pixels) {
  for (int level = 0; level < kLodLevels - 1; ++level) {
    if (diameter_pixels >= kLodMinPixels[level]) return level;
  }
  return kLodLevels - 1;
}

double CameraView::focal_pixels(int height) const {
  return 0.5 * height / std::tan(0.5 * fov_y_rad);
}

Eigen::Matrix4f CameraView::view_projection(const Vector3d& origin) const {
  const Vector3d f = forward(), r = right(), u = true_up();
  const Vector3d e = eye - origin;
  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
  view.row(0) << r.transpose(), -r.dot(e);
  view.row(1) << u.transpose(), -u.dot(e);
  view.row(2) << -f.transpose(), f.dot(e);
  const double t = 1.0 / std::tan(0.5 * fov_y_rad);
  const double n = near_plane, fa = far_plane;
  Eigen::Matrix4d projection = Eigen::Matrix4d::Zero();
  projection(0, 0) = t / aspect;
  projection(1, 1) = t;
  projection(2, 2) = -(fa + n) / (fa - n);
  projection(2, 3) = -2.0 * fa * n / (fa - n);
  projection(3, 2) = -1.0;
  return (projection * view).cast<float>();
}

void Bounds::add(const Vector3d& p) {
  if (!p.allFinite()) return;
  min = min.cwiseMin(p);
  max = max.cwiseMax(p);
}

Bounds frame_bounds(const std::vector<const RingFrame*>& frames) {
  Bounds bounds;
  for (const RingFrame* frame : frames) {
    if (!frame) continue;
    for (int ring = 0; ring < frame->size(); ++ring) bounds.add(frame->position.col(ring));
  }
  return bounds;
}

CameraView make_camera(const Scene& scene, const Bounds& bounds, double aspect,
                       const std::optional<Vector3d>& view_from) {
  CameraView view;
  view.aspect = aspect;
  view.fov_y_rad = scene.camera.fov_deg * kPi / 180.0;
  const double ring_extent = scene.ring.centre_radius + scene.ring.wire_radius;
  const Vector3d center = bounds.empty() ? scene.weave.center : bounds.center();
  const double radius = std::max(bounds.radius(), 0.0) + ring_extent;
  if (view_from || scene.camera.automatic) {
    frame_automatically(view, bounds, center, radius, ring_extent,
                        view_from.value_or(kAutomaticViewFrom));
  } else {
    view.eye = scene.camera.position;
    view.target = scene.camera.target;
  }
  // world up, unless the camera looks straight up or down
  const Vector3d forward = (view.target - view.eye).normalized();
  view.up = Vector3d::UnitY();
  if (std::abs(forward.y()) > 0.999) view.up = Vector3d(0.0, 0.0, forward.y() < 0 ? -1.0 : 1.0);

  // depth range: everything within a few fabric radii of the fabric's centre
  const double distance = (view.eye - center).norm();
  view.near_plane = std::max(distance - 1.5 * radius, 0.005 * distance);
  view.far_plane = distance + 5.0 * radius;
  return view;
}

Eigen::Matrix3f sky_ray_basis(const CameraView& camera) {
  const double tan_y = std::tan(0.5 * camera.fov_y_rad), tan_x = tan_y * camera.aspect;
  Eigen::Matrix3f basis;
  basis.col(0) = (camera.right() * tan_x).cast<float>();
  basis.col(1) = (camera.true_up() * tan_y).cast<float>();
  basis.col(2) = camera.forward().cast<float>();
  return basis;
}

SharedView shared_view(const Scene& scene, const std::vector<const RingFrame*>& frames,
                       double aspect, const std::optional<Vector3d>& view_from) {
  const Bounds bounds = frame_bounds(frames);
  SharedView view;
  view.camera = make_camera(scene, bounds, aspect, view_from);
  view.origin = view.camera.target;
  view.focus = bounds.empty() ? view.camera.target : bounds.center();
  view.fabric_radius =
      std::max(bounds.radius(), 0.0) + scene.ring.centre_radius + scene.ring.wire_radius;
  view.checker = static_cast<float>(round_tile(0.5 * view.fabric_radius));
  return view;
}

RingFrustum ring_frustum(const CameraView& camera, double ring_radius) {
  RingFrustum f;
  f.eye = camera.eye;
  f.forward = camera.forward(), f.right = camera.right(), f.up = camera.true_up();
  f.near_plane = camera.near_plane, f.far_plane = camera.far_plane;
  f.tan_y = std::tan(0.5 * camera.fov_y_rad), f.tan_x = f.tan_y * camera.aspect;
  f.radius = ring_radius;
  f.slack_x = ring_radius * std::sqrt(1.0 + f.tan_x * f.tan_x);
  f.slack_y = ring_radius * std::sqrt(1.0 + f.tan_y * f.tan_y);
  return f;
}

bool ring_visible(const RingFrustum& f, const Vector3d& p, double& depth) {
  const Vector3d relative = p - f.eye;
  depth = relative.dot(f.forward);
  if (depth + f.radius < f.near_plane || depth - f.radius > f.far_plane) return false;
  if (std::abs(relative.dot(f.right)) - depth * f.tan_x > f.slack_x) return false;
  return std::abs(relative.dot(f.up)) - depth * f.tan_y <= f.slack_y;
}

int LodChoice::level(double depth) const {
  const double pixels = 2.0 * ring_radius * focal_pixels / std::max(depth, 1e-9);
  return enabled ? lod_for_pixels(scale * pixels) : 0;
}

Eigen::Vector4f shader_quaternion(const Eigen::Vector4d& wxyz) {
  const Eigen::Vector4d q = wxyz.normalized();
  return {static_cast<float>(q[1]), static_cast<float>(q[2]), static_cast<float>(q[3]),
          static_cast<float>(q[0])};
}

void pack_ring_instances(const RingFrame& frame, const RingFrustum& frustum, const LodChoice& lod,
                         const Vector3d& origin, RingInstances& out) {
  // cull and bucket by level
  for (auto& bucket : out.buckets) bucket.clear();
  for (int ring = 0; ring < frame.size(); ++ring) {
    const Vector3d p = frame.position.col(ring);
    const Eigen::Vector4d q = frame.orientation.col(ring);
    if (!p.allFinite() || !q.allFinite() || q.norm() < 1e-12) continue;
    double depth = 0.0;
    if (!ring_visible(frustum, p, depth)) continue;
    out.buckets[lod.level(depth)].push_back({depth, ring});
  }
  // sort each level and append its instances
  out.data.clear();
  out.offsets[0] = 0;
  for (int level = 0; level < kLodLevels; ++level) {
    auto& bucket = out.buckets[level];
    if (level < kMeshLevels) {
      std::sort(bucket.begin(), bucket.end());
    } else {
      std::sort(bucket.begin(), bucket.end(), std::greater<>());
    }
    out.offsets[level + 1] = out.offsets[level] + static_cast<int>(bucket.size());
    for (const auto& [depth, ring] : bucket) {
      const Vector3d p = frame.position.col(ring) - origin;
      const Eigen::Vector4f q = shader_quaternion(frame.orientation.col(ring));
      out.data.insert(out.data.end(), {static_cast<float>(p.x()), static_cast<float>(p.y()),
                                       static_cast<float>(p.z()), q[0], q[1], q[2], q[3]});
    }
  }
}

}  // namespace chainmail::render
