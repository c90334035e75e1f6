// The renderer's CPU geometry: torus winding, the ray-cast box, the cloth mesh.
#include <gtest/gtest.h>

#include "core/scene.hpp"
#include "core/weave.hpp"
#include "render/mesh.hpp"
#include "render/scene_view.hpp"
#include "test_scenes.hpp"

namespace chainmail::render {
namespace {

Eigen::Vector3d vertex(const Mesh& mesh, std::uint32_t index, int offset) {
  const float* v = &mesh.vertices[static_cast<size_t>(index) * mesh.stride + offset];
  return {v[0], v[1], v[2]};
}

TEST(RenderMesh, TorusTrianglesFaceOutwardAndLieOnTheTorus) {
  const double a = 0.0008, c = 0.0048;
  for (const auto& [u, v] : kLodSegments) {
    const Mesh mesh = torus_mesh(a, c, u, v);
    EXPECT_EQ(mesh.indices.size(), static_cast<size_t>(u * v * 6));
    for (size_t t = 0; t < mesh.indices.size(); t += 3) {
      const Eigen::Vector3d p0 = vertex(mesh, mesh.indices[t], 0),
                            p1 = vertex(mesh, mesh.indices[t + 1], 0),
                            p2 = vertex(mesh, mesh.indices[t + 2], 0);
      const Eigen::Vector3d n = vertex(mesh, mesh.indices[t], 3) +
                                vertex(mesh, mesh.indices[t + 1], 3) +
                                vertex(mesh, mesh.indices[t + 2], 3);
      ASSERT_GT((p1 - p0).cross(p2 - p0).dot(n), 0.0) << "triangle " << t / 3;
    }
    for (int k = 0; k < mesh.vertex_count(); ++k) {
      const Eigen::Vector3d p = vertex(mesh, k, 0);
      // distance from the centre circle (radius c in the X/Z plane) is the wire radius
      const double radial = std::hypot(p.x(), p.z()) - c;
      ASSERT_NEAR(std::hypot(radial, p.y()), a, 1e-6 * c);
    }
  }
}

TEST(RenderMesh, BoxIsTheUnitCubeSeenFromOutside) {
  const Mesh box = box_mesh();
  ASSERT_EQ(box.indices.size(), 36u);  // 6 faces, 2 triangles each
  for (size_t t = 0; t < box.indices.size(); t += 3) {
    const Eigen::Vector3d p0 = vertex(box, box.indices[t], 0),
                          p1 = vertex(box, box.indices[t + 1], 0),
                          p2 = vertex(box, box.indices[t + 2], 0);
    // counter-clockwise seen from outside: the winding normal points away from the centre
    ASSERT_GT((p1 - p0).cross(p2 - p0).dot(p0 + p1 + p2), 0.0) << "triangle " << t / 3;
  }
  for (int k = 0; k < box.vertex_count(); ++k) {
    EXPECT_DOUBLE_EQ(vertex(box, k, 0).cwiseAbs().maxCoeff(), 1.0);
    EXPECT_DOUBLE_EQ(vertex(box, k, 0).cwiseAbs().minCoeff(), 1.0);  // corners only
  }
}

// a plain grid of point masses 1 cm apart (the cloth scenes' weave)
Scene grid_scene(int rows, int cols) {
  Scene scene = test::sheet_scene(rows, cols, WeaveType::grid);
  scene.weave.spacing = 0.01;
  return scene;
}

TEST(RenderMesh, SupportDiskSitsAHairAboveTheTableTopItRestsOn) {
  // the drape table's collider and its support share a top at 0.1 m: drawn coplanar, they would
  // fight for depth; the disk is lifted by less than a tenth of a wire radius
  Scene scene = test::sheet_scene(2, 2);
  Collider table;
  table.type = Collider::Type::cylinder;
  table.center = Vec3(0.0, 0.05, 0.0);
  table.radius = 0.03, table.half_height = 0.05;
  scene.colliders.push_back(table);
  scene.support = Support{Vec3(0.0, 0.1, 0.0), 0.03};
  const Mesh mesh = scene_mesh(scene, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 1.0);
  double table_top = -1.0, disk_top = -1.0;
  for (int k = 0; k < mesh.vertex_count(); ++k) {
    const Eigen::Vector3d p = vertex(mesh, k, 0), color = vertex(mesh, k, 6);
    const bool disk = std::abs(color.x() - 0.52) < 1e-6;  // the support's colour
    (disk ? disk_top : table_top) = std::max(disk ? disk_top : table_top, p.y());
  }
  EXPECT_NEAR(table_top, 0.1, 1e-7);
  EXPECT_GT(disk_top - table_top, 1e-5);
  EXPECT_LT(disk_top - table_top, 0.1 * scene.ring.wire_radius);
}

TEST(RenderMesh, ClothMeshJoinsGridNeighboursIntoQuads) {
  const Scene scene = grid_scene(3, 4);
  const Weave weave = make_weave(scene.weave, scene.ring);
  RingFrame frame;
  frame.resize(weave.size());
  frame.position = weave.rest_position;
  frame.orientation = weave.rest_orientation;
  const Mesh mesh = cloth_mesh(frame, weave, 1, Eigen::Vector3d::Zero());
  EXPECT_EQ(mesh.stride, 9);
  EXPECT_EQ(mesh.indices.size(), static_cast<size_t>((3 - 1) * (4 - 1) * 6));
  // a flat sheet: every normal is the sheet normal (either side)
  for (int k = 0; k < mesh.vertex_count(); ++k) {
    EXPECT_NEAR(std::abs(vertex(mesh, k, 3).dot(weave.normal_axis)), 1.0, 1e-6);
  }
  // subdivided for displacement: s^2 quads per quad
  const Mesh fine = cloth_mesh(frame, weave, 4, Eigen::Vector3d::Zero());
  EXPECT_EQ(fine.indices.size(), mesh.indices.size() * 16);
  // a ring gone to NaN drops its quads instead of poisoning the mesh
  frame.position(0, 0) = std::nan("");
  EXPECT_LT(cloth_mesh(frame, weave, 1, Eigen::Vector3d::Zero()).indices.size(),
            mesh.indices.size());
}

TEST(RenderMesh, ClothMeshCarriesEachRingsStrain) {
  const Scene scene = grid_scene(3, 4);
  const Weave weave = make_weave(scene.weave, scene.ring);
  RingFrame frame;
  frame.resize(weave.size());
  frame.orientation = weave.rest_orientation;
  frame.position = weave.rest_position;
  for (double e : ring_strain(frame, weave)) EXPECT_NEAR(e, 0.0, 1e-12);
  // the sheet stretched by 5 % (then compressed by 5 %) about one ring: every vertex carries it
  for (const double scale : {1.05, 0.95}) {
    frame.position = weave.rest_position * scale;
    frame.position.colwise() += Vec3(0.3, -0.2, 0.1);
    for (double e : ring_strain(frame, weave)) EXPECT_NEAR(e, scale - 1.0, 1e-9);
    const Mesh mesh = cloth_mesh(frame, weave, 2, Eigen::Vector3d::Zero());
    for (int k = 0; k < mesh.vertex_count(); ++k) {
      EXPECT_NEAR(mesh.vertices[static_cast<size_t>(k) * mesh.stride + 8], scale - 1.0, 1e-6);
    }
  }
  // one ring pulled out of the sheet: it and its neighbours stretch, a far ring does not
  frame.position = weave.rest_position;
  frame.position.col(0) += 0.5 * scene.weave.spacing * weave.normal_axis;
  const std::vector<double> strain = ring_strain(frame, weave);
  EXPECT_GT(strain[0], 0.05);
  EXPECT_GT(strain[weave.neighbours[0][1] >= 0 ? weave.neighbours[0][1] : weave.neighbours[0][0]],
            0.0);
  EXPECT_NEAR(strain[weave.size() - 1], 0.0, 1e-12);
}

}  // namespace
}  // namespace chainmail::render
