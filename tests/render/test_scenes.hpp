// Scenes for the renderer's tests, built as plain structs: the renderer sees only Scene, and the
// scene-file reader belongs to the command line.
#pragma once

#include "core/frame.hpp"
#include "core/scene.hpp"
#include "core/weave.hpp"

namespace chainmail::render::test {

// a rows x cols sheet of `type` with rings of wire 1.6 mm, inner diameter 8 mm, steel; automatic
// camera, no colliders
inline Scene sheet_scene(int rows, int cols, WeaveType type = WeaveType::four_in_one) {
  Scene scene;
  scene.name = "test";
  scene.ring = RingGeometry::from_diameters(0.0016, 0.008, 7850.0);
  scene.weave.type = type;
  scene.weave.rows = rows;
  scene.weave.cols = cols;
  return scene;
}

// a fixed camera at `position` looking at `target`
inline Scene with_camera(Scene scene, const Vec3& position, const Vec3& target,
                         double fov_deg = 40.0) {
  scene.camera.automatic = false;
  scene.camera.position = position;
  scene.camera.target = target;
  scene.camera.fov_deg = fov_deg;
  return scene;
}

// a ground plane (normal +Y) at height `y`
inline Scene with_ground(Scene scene, double y) {
  Collider ground;
  ground.type = Collider::Type::plane;
  ground.center = Vec3(0.0, y, 0.0);
  scene.colliders.push_back(ground);
  return scene;
}

// the weave's rings at rest
inline RingFrame rest_frame(const Weave& weave) {
  RingFrame frame;
  frame.resize(weave.size());
  frame.position = weave.rest_position;
  frame.orientation = weave.rest_orientation;
  frame.velocity.setZero();
  return frame;
}

}  // namespace chainmail::render::test
