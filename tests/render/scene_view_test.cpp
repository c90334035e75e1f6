// What the renderer draws, without a GL context: level of detail by size on screen, culling
// against the view frustum, instance packing, camera framing and the shared view of all panels.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "core/scene.hpp"
#include "core/weave.hpp"
#include "render/scene_view.hpp"
#include "test_scenes.hpp"

namespace chainmail::render {
namespace {

using Eigen::Vector3d;

constexpr double kPi = 3.141592653589793;

// eye at z = 1 looking down -Z at the origin, 60 degree field, square image
CameraView test_camera() {
  CameraView camera;
  camera.eye = Vector3d(0.0, 0.0, 1.0);
  camera.target = Vector3d::Zero();
  camera.up = Vector3d::UnitY();
  camera.fov_y_rad = kPi / 3.0;
  camera.aspect = 1.0;
  camera.near_plane = 0.1;
  camera.far_plane = 10.0;
  return camera;
}

TEST(RenderSceneView, FinerLevelsForBiggerRings) {
  EXPECT_EQ(lod_for_pixels(500.0), 0);
  EXPECT_EQ(lod_for_pixels(1.0), kLodLevels - 1);
  for (double px = 1.0; px < 200.0; px *= 1.1) {
    EXPECT_GE(lod_for_pixels(px), lod_for_pixels(px * 1.1));
  }
  // the thresholds themselves: a level starts at its smallest diameter
  for (int level = 0; level + 1 < kLodLevels; ++level) {
    EXPECT_EQ(lod_for_pixels(kLodMinPixels[level]), level);
    EXPECT_EQ(lod_for_pixels(std::nextafter(kLodMinPixels[level], 0.0)), level + 1);
  }
}

TEST(RenderSceneView, LevelOfDetailPicksByProjectedSize) {
  // a ring 2 cm across at 1000 px per metre at unit depth: 20 / depth pixels
  const LodChoice lod{true, 1.0, 0.01, 1000.0};
  auto depth_for_pixels = [](double pixels) { return 20.0 / pixels; };
  EXPECT_EQ(lod.level(depth_for_pixels(kLodMinPixels[0] * 1.01)), 0);
  EXPECT_EQ(lod.level(depth_for_pixels(kLodMinPixels[0] * 0.99)), 1);
  EXPECT_EQ(lod.level(depth_for_pixels(kLodMinPixels[1] * 1.01)), 1);
  EXPECT_EQ(lod.level(depth_for_pixels(kLodMinPixels[1] * 0.99)), kLodLevels - 1);
  // nearer is never coarser
  for (double depth = 0.01; depth < 5.0; depth *= 1.2) {
    EXPECT_LE(lod.level(depth), lod.level(depth * 1.2)) << depth;
  }

  // the scale shifts the thresholds: at half scale a 150 px ring is ray-cast, at 0 every ring
  const double depth_150px = depth_for_pixels(150.0);
  EXPECT_EQ(lod.level(depth_150px), 1);
  EXPECT_EQ((LodChoice{true, 0.5, 0.01, 1000.0}.level(depth_150px)), kLodLevels - 1);
  EXPECT_EQ((LodChoice{true, 2.0, 0.01, 1000.0}.level(depth_150px)), 0);
  EXPECT_EQ((LodChoice{true, 0.0, 0.01, 1000.0}.level(0.001)), kLodLevels - 1);
  // level of detail off: the finest mesh however small
  EXPECT_EQ((LodChoice{false, 1.0, 0.01, 1000.0}.level(1000.0)), 0);
}

TEST(RenderSceneView, CullingKeepsWhatIsInsideAndDropsWhatIsOutside) {
  const double r = 0.01;
  const RingFrustum frustum = ring_frustum(test_camera(), r);
  double depth = 0.0;
  EXPECT_TRUE(ring_visible(frustum, Vector3d::Zero(), depth));
  EXPECT_DOUBLE_EQ(depth, 1.0);

  // along the view axis: behind the eye, beyond the far plane, across the near plane
  EXPECT_FALSE(ring_visible(frustum, Vector3d(0.0, 0.0, 2.0), depth));
  EXPECT_FALSE(ring_visible(frustum, Vector3d(0.0, 0.0, 1.0 - 10.0 - 2.0 * r), depth));
  EXPECT_TRUE(ring_visible(frustum, Vector3d(0.0, 0.0, 1.0 - 10.0 - 0.5 * r), depth));
  EXPECT_TRUE(ring_visible(frustum, Vector3d(0.0, 0.0, 1.0 - 0.1 + 0.5 * r), depth));
  EXPECT_FALSE(ring_visible(frustum, Vector3d(0.0, 0.0, 1.0 - 0.1 + 2.0 * r), depth));

  // across: the side planes at depth 1 are tan(30 deg) from the axis; a ring whose sphere
  // reaches over them is kept (its distance to the plane is (x - tan) cos), one clear of it not
  const double edge = std::tan(kPi / 6.0), to_plane = 1.0 / std::cos(kPi / 6.0);
  for (const Vector3d& axis : {Vector3d(Vector3d::UnitX()), Vector3d(Vector3d::UnitY())}) {
    for (double sign : {-1.0, 1.0}) {
      EXPECT_TRUE(ring_visible(frustum, sign * (edge - 0.5) * axis, depth));
      EXPECT_TRUE(ring_visible(frustum, sign * (edge + 0.9 * r * to_plane) * axis, depth))
          << axis.transpose() << " " << sign;
      EXPECT_FALSE(ring_visible(frustum, sign * (edge + 1.1 * r * to_plane) * axis, depth))
          << axis.transpose() << " " << sign;
    }
  }
  // a wider image keeps more across but not more up and down
  CameraView wide = test_camera();
  wide.aspect = 2.0;
  const RingFrustum wide_frustum = ring_frustum(wide, r);
  EXPECT_TRUE(ring_visible(wide_frustum, Vector3d(1.5 * edge, 0.0, 0.0), depth));
  EXPECT_FALSE(ring_visible(wide_frustum, Vector3d(0.0, 1.5 * edge, 0.0), depth));
}

TEST(RenderSceneView, ShaderQuaternionIsUnitAndVectorPartFirst) {
  const Eigen::Vector4f q = shader_quaternion(Eigen::Vector4d(1.0, 2.0, 3.0, 4.0));  // w, x, y, z
  const float n = std::sqrt(30.0f);
  EXPECT_NEAR(q[0], 2.0f / n, 1e-7f);
  EXPECT_NEAR(q[1], 3.0f / n, 1e-7f);
  EXPECT_NEAR(q[2], 4.0f / n, 1e-7f);
  EXPECT_NEAR(q[3], 1.0f / n, 1e-7f);
  // it rotates like the frame's quaternion: local +Y (the ring axis) to the world axis
  const Quat frame_q = Quat(1.0, 2.0, 3.0, 4.0).normalized();
  const Quat shader_q(q[3], q[0], q[1], q[2]);
  EXPECT_LT((shader_q * Vec3::UnitY() - frame_q * Vec3::UnitY()).norm(), 1e-6);
}

// rings along the view axis at the given depths, identity orientation
RingFrame rings_at_depths(const std::vector<double>& depths) {
  RingFrame frame;
  frame.resize(static_cast<int>(depths.size()));
  frame.velocity.setZero();
  for (int ring = 0; ring < frame.size(); ++ring) {
    frame.position.col(ring) = Vector3d(0.001 * ring, 0.0, 1.0 - depths[ring]);
    frame.set_quat(ring, Quat::Identity());
  }
  return frame;
}

// centre of packed instance `k`
Vector3d packed_centre(const RingInstances& instances, int k) {
  const float* v = &instances.data[static_cast<size_t>(k) * kInstanceFloats];
  return {v[0], v[1], v[2]};
}

TEST(RenderSceneView, PackingSortsLevelsAndWritesEachInstance) {
  // 80 / depth pixels: level 0 nearer than 0.42, level 1 to 0.83, then ray-cast
  const LodChoice lod{true, 1.0, 0.01, 4000.0};
  const RingFrustum frustum = ring_frustum(test_camera(), 0.01);
  RingFrame frame = rings_at_depths({1.0, 0.3, 0.6, 2.0, 0.2, -1.0, 0.9, 0.9, 0.9, 0.9});
  frame.position(1, 6) = std::numeric_limits<double>::quiet_NaN();  // a ring gone to NaN
  frame.orientation.col(7).setZero();                               // no orientation
  frame.orientation(2, 8) = std::numeric_limits<double>::infinity();
  frame.set_quat(9, Quat(Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, 0.5).normalized())));
  frame.orientation.col(9) *= 3.0;  // not unit length: packed normalised
  const Vector3d origin(0.1, -0.2, 0.3);
  RingInstances instances;
  pack_ring_instances(frame, frustum, lod, origin, instances);

  // kept: 4, 1 (level 0); 2 (level 1); 3, 0, 9 (ray-cast); dropped: 5 behind, 6-8 invalid
  ASSERT_EQ(instances.total(), 6);
  EXPECT_EQ(instances.count(0), 2);
  EXPECT_EQ(instances.count(1), 1);
  EXPECT_EQ(instances.count(2), 3);
  EXPECT_EQ(instances.offsets[0], 0);
  ASSERT_EQ(instances.data.size(), 6u * kInstanceFloats);
  // meshes front to back, the blended ray-cast level back to front
  const int expected_order[] = {4, 1, 2, 3, 0, 9};
  for (int k = 0; k < 6; ++k) {
    const Vector3d expected = frame.position.col(expected_order[k]) - origin;
    EXPECT_LT((packed_centre(instances, k) - expected).norm(), 1e-6) << "instance " << k;
  }
  // orientation of every instance: (x, y, z, w), unit
  for (int k = 0; k < 6; ++k) {
    const Eigen::Vector4f expected = shader_quaternion(frame.orientation.col(expected_order[k]));
    const Eigen::Map<const Eigen::Vector4f> packed(&instances.data[k * kInstanceFloats + 3]);
    EXPECT_EQ(packed, expected) << "instance " << k;
    EXPECT_NEAR(packed.norm(), 1.0f, 1e-6f);
  }

  // the storage is reused: a smaller frame leaves nothing of the last one behind
  pack_ring_instances(rings_at_depths({2.0}), frustum, lod, origin, instances);
  EXPECT_EQ(instances.total(), 1);
  EXPECT_EQ(instances.count(kLodLevels - 1), 1);
  EXPECT_EQ(instances.data.size(), static_cast<size_t>(kInstanceFloats));
  pack_ring_instances(rings_at_depths({}), frustum, lod, origin, instances);
  EXPECT_EQ(instances.total(), 0);
  EXPECT_TRUE(instances.data.empty());
}

TEST(RenderSceneView, AutomaticCameraSeesTheWholeFabricFromAboveAndInFront) {
  const Scene scene = test::sheet_scene(10, 10);
  const Weave weave = make_weave(scene.weave, scene.ring);
  RingFrame frame;
  frame.resize(weave.size());
  frame.position = weave.rest_position;
  const Bounds bounds = frame_bounds({&frame});
  const CameraView camera = make_camera(scene, bounds, 4.0 / 3.0);
  EXPECT_GT(camera.eye.y(), bounds.center().y());
  EXPECT_GT(camera.eye.z(), bounds.center().z());
  const Eigen::Matrix4f vp = camera.view_projection(Eigen::Vector3d::Zero());
  const RingFrustum frustum =
      ring_frustum(camera, scene.ring.centre_radius + scene.ring.wire_radius);
  for (int ring = 0; ring < frame.size(); ++ring) {
    const Eigen::Vector4f clip =
        vp * Eigen::Vector4f(frame.position(0, ring), frame.position(1, ring),
                             frame.position(2, ring), 1.0f);
    const Eigen::Vector3f ndc = clip.head<3>() / clip.w();
    EXPECT_LT(ndc.cwiseAbs().maxCoeff(), 1.0f) << "ring " << ring << " off screen";
    double depth = 0.0;
    EXPECT_TRUE(ring_visible(frustum, frame.position.col(ring), depth)) << "ring " << ring;
  }
}

TEST(RenderSceneView, ViewFromFramesTheFabricFromThatDirectionWhateverTheSceneCamera) {
  // a fixed scene camera looking elsewhere: a direction overrides it and frames the sheet
  const Scene scene = test::with_camera(test::sheet_scene(8, 8), Vec3(5, 5, 5), Vec3(4, 4, 4));
  const Weave weave = make_weave(scene.weave, scene.ring);
  RingFrame frame;
  frame.resize(weave.size());
  frame.position = weave.rest_position;
  const Bounds bounds = frame_bounds({&frame});
  for (const Vector3d& from : {Vector3d(0, 1, 0), Vector3d(1, 0.15, 0), Vector3d(0, 0.15, 1)}) {
    const CameraView camera = make_camera(scene, bounds, 16.0 / 9.0, from);
    EXPECT_NEAR((camera.eye - camera.target).normalized().dot(from.normalized()), 1.0, 1e-12);
    EXPECT_TRUE(camera.up.allFinite() && camera.right().allFinite()) << from.transpose();
    const Eigen::Matrix4f vp = camera.view_projection(Vector3d::Zero());
    for (int ring = 0; ring < frame.size(); ++ring) {
      const Eigen::Vector4f clip =
          vp * Eigen::Vector4f(frame.position(0, ring), frame.position(1, ring),
                               frame.position(2, ring), 1.0f);
      ASSERT_LT((clip.head<3>() / clip.w()).cwiseAbs().maxCoeff(), 1.0f)
          << "ring " << ring << " off screen from " << from.transpose();
    }
  }
  // without a direction the scene's own camera stays
  EXPECT_EQ(make_camera(scene, bounds, 1.0).eye, Vector3d(5, 5, 5));
}

TEST(RenderSceneView, SkyRayBasisSpansTheFieldOfView) {
  CameraView camera = test_camera();
  camera.aspect = 1.5;
  const Eigen::Matrix3f basis = sky_ray_basis(camera);
  const double tan_y = std::tan(kPi / 6.0);
  EXPECT_NEAR(basis.col(0).norm(), tan_y * 1.5, 1e-6);
  EXPECT_NEAR(basis.col(1).norm(), tan_y, 1e-6);
  EXPECT_LT((basis.col(2) - Eigen::Vector3f(0.0f, 0.0f, -1.0f)).norm(), 1e-6f);
  // the top right corner of the image looks up, right and forward
  const Eigen::Vector3f corner = basis * Eigen::Vector3f(1.0f, 1.0f, 1.0f);
  EXPECT_GT(corner.x(), 0.0f);
  EXPECT_GT(corner.y(), 0.0f);
  EXPECT_LT(corner.z(), 0.0f);
}

TEST(RenderSceneView, SharedViewFramesAllPanelsAndSizesTheChecker) {
  const Scene scene =
      test::with_camera(test::sheet_scene(2, 2), Vec3(0.0, 1.0, 2.0), Vec3(0.0, 0.5, 0.0));
  const double pad = scene.ring.centre_radius + scene.ring.wire_radius;
  // two panels, one ring each, (2 half, rise) apart: the box's half diagonal plus one ring
  auto frames_apart = [&](double half, double rise) {
    RingFrame a, b;
    a.resize(1), b.resize(1);
    a.position.col(0) = Vector3d(-half, 0.3 - 0.5 * rise, 0.0);
    b.position.col(0) = Vector3d(half, 0.3 + 0.5 * rise, 0.0);
    return std::pair{a, b};
  };
  const auto [a, b] = frames_apart(0.3, 0.2);
  const SharedView view = shared_view(scene, {&a, &b}, 2.0);
  EXPECT_EQ(view.origin, view.camera.target);
  EXPECT_EQ(view.camera.eye, Vector3d(0.0, 1.0, 2.0));
  EXPECT_DOUBLE_EQ(view.camera.aspect, 2.0);
  EXPECT_LT((view.focus - Vector3d(0.0, 0.3, 0.0)).norm(), 1e-12);
  EXPECT_NEAR(view.fabric_radius, std::hypot(0.3, 0.1) + pad, 1e-12);

  // checker tile: the largest 1, 2, 5 x 10^k up to half the fabric radius
  for (const auto& [half_radius, tile] :
       {std::pair{0.037, 0.02}, {0.6, 0.5}, {0.15, 0.1}, {0.0999, 0.05}, {3.0, 2.0}}) {
    const auto [p, q] = frames_apart(2.0 * half_radius - pad, 0.0);
    EXPECT_NEAR(shared_view(scene, {&p, &q}, 1.0).checker, tile, 1e-6 * tile) << half_radius;
  }
  // no rings at all: the camera's target is the focus
  RingFrame none;
  none.resize(0);
  const SharedView empty = shared_view(scene, {&none, nullptr}, 1.0);
  EXPECT_EQ(empty.focus, empty.camera.target);
  EXPECT_DOUBLE_EQ(empty.fabric_radius, pad);
}

}  // namespace
}  // namespace chainmail::render
