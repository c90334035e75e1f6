#include "render/mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "core/ring.hpp"

namespace chainmail::render {
namespace {

using Eigen::Vector3d;
constexpr double kPi = std::numbers::pi;

void push(std::vector<float>& out, const Vector3d& v) {
  out.push_back(static_cast<float>(v.x()));
  out.push_back(static_cast<float>(v.y()));
  out.push_back(static_cast<float>(v.z()));
}

// a coloured vertex of the scene mesh (stride 10)
struct SceneMeshBuilder {
  Mesh mesh{10, {}, {}};
  Vector3d origin;
  Eigen::Vector4d color;

  std::uint32_t vertex(const Vector3d& p, const Vector3d& n) {
    const auto index = static_cast<std::uint32_t>(mesh.vertex_count());
    push(mesh.vertices, p - origin);
    push(mesh.vertices, n);
    for (int k = 0; k < 4; ++k) mesh.vertices.push_back(static_cast<float>(color[k]));
    return index;
  }
  void triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    mesh.indices.insert(mesh.indices.end(), {a, b, c});
  }
  // flat quad with corners counter-clockwise around n
  void quad(const Vector3d& a, const Vector3d& b, const Vector3d& c, const Vector3d& d,
            const Vector3d& n) {
    const auto i0 = vertex(a, n), i1 = vertex(b, n), i2 = vertex(c, n), i3 = vertex(d, n);
    triangle(i0, i1, i2);
    triangle(i0, i2, i3);
  }
};

// two unit vectors completing n to an orthonormal basis
void tangents(const Vector3d& n, Vector3d& t1, Vector3d& t2) {
  t1 = (std::abs(n.x()) < 0.9 ? Vector3d::UnitX() : Vector3d::UnitY()).cross(n).normalized();
  t2 = n.cross(t1);
}

void add_sphere(SceneMeshBuilder& b, const Vector3d& center, double radius) {
  constexpr int kAround = 32, kUp = 16;
  const auto first = static_cast<std::uint32_t>(b.mesh.vertex_count());
  for (int i = 0; i <= kUp; ++i) {
    const double theta = kPi * i / kUp;
    for (int k = 0; k <= kAround; ++k) {
      const double phi = 2.0 * kPi * k / kAround;
      const Vector3d n(std::sin(theta) * std::cos(phi), std::cos(theta),
                       std::sin(theta) * std::sin(phi));
      b.vertex(center + radius * n, n);
    }
  }
  for (int i = 0; i < kUp; ++i) {
    for (int k = 0; k < kAround; ++k) {
      const std::uint32_t a = first + i * (kAround + 1) + k, c = a + kAround + 1;
      b.triangle(a, a + 1, c);
      b.triangle(a + 1, c + 1, c);
    }
  }
}

// the six faces of the box center +- half: corners counter-clockwise seen from outside, then the
// outward normal, passed to quad(c0, c1, c2, c3, n)
template <class Quad>
void box_faces(const Vector3d& center, const Vector3d& half, Quad&& quad) {
  for (int axis = 0; axis < 3; ++axis) {
    for (double sign : {-1.0, 1.0}) {
      Vector3d n = Vector3d::Zero();
      n[axis] = sign;
      Vector3d u = Vector3d::Zero(), v = Vector3d::Zero();
      u[(axis + 1) % 3] = half[(axis + 1) % 3];
      v[(axis + 2) % 3] = half[(axis + 2) % 3];
      if (sign < 0) std::swap(u, v);  // keeps u x v along n
      const Vector3d f = center + n.cwiseProduct(half);
      quad(f - u - v, f + u - v, f + u + v, f - u + v, n);
    }
  }
}

void add_box(SceneMeshBuilder& b, const Vector3d& center, const Vector3d& half) {
  box_faces(center, half,
            [&](const Vector3d& c0, const Vector3d& c1, const Vector3d& c2, const Vector3d& c3,
                const Vector3d& n) { b.quad(c0, c1, c2, c3, n); });
}

void add_cylinder(SceneMeshBuilder& b, const Vector3d& center, double radius, double half_height) {
  constexpr int kAround = 40;
  const Vector3d up = Vector3d::UnitY();
  for (int k = 0; k < kAround; ++k) {
    const double p0 = 2.0 * kPi * k / kAround, p1 = 2.0 * kPi * (k + 1) / kAround;
    const Vector3d d0(std::cos(p0), 0, std::sin(p0)), d1(std::cos(p1), 0, std::sin(p1));
    // side (outward normals per vertex, smooth) and the two caps
    const auto a = b.vertex(center + radius * d0 - half_height * up, d0);
    const auto c = b.vertex(center + radius * d1 - half_height * up, d1);
    const auto e = b.vertex(center + radius * d1 + half_height * up, d1);
    const auto f = b.vertex(center + radius * d0 + half_height * up, d0);
    b.triangle(a, e, c);
    b.triangle(a, f, e);
    const auto top = b.vertex(center + half_height * up, up);
    const auto t0 = b.vertex(center + radius * d0 + half_height * up, up);
    const auto t1 = b.vertex(center + radius * d1 + half_height * up, up);
    b.triangle(top, t1, t0);
    const auto bottom = b.vertex(center - half_height * up, -up);
    const auto b0 = b.vertex(center + radius * d0 - half_height * up, -up);
    const auto b1 = b.vertex(center + radius * d1 - half_height * up, -up);
    b.triangle(bottom, b0, b1);
  }
}

}  // namespace

Mesh torus_mesh(double wire_radius, double centre_radius, int segments_u, int segments_v) {
  const RingSurface surface = ring_surface(wire_radius, centre_radius, segments_u, segments_v);
  Mesh mesh;
  mesh.stride = 6;
  for (int v = 0; v < surface.vertices(); ++v) {
    const float* position = surface.position.data() + 3 * v;
    const float* normal = surface.normal.data() + 3 * v;
    mesh.vertices.insert(mesh.vertices.end(), position, position + 3);
    mesh.vertices.insert(mesh.vertices.end(), normal, normal + 3);
  }
  mesh.indices = surface.index;
  return mesh;
}

Mesh box_mesh() {
  Mesh mesh;
  mesh.stride = 6;
  box_faces(Vector3d::Zero(), Vector3d::Ones(),
            [&](const Vector3d& c0, const Vector3d& c1, const Vector3d& c2, const Vector3d& c3,
                const Vector3d& n) {
              const auto first = static_cast<std::uint32_t>(mesh.vertex_count());
              for (const Vector3d* corner : {&c0, &c1, &c2, &c3}) {
                push(mesh.vertices, *corner);
                push(mesh.vertices, n);
              }
              mesh.indices.insert(mesh.indices.end(),
                                  {first, first + 1, first + 2, first, first + 2, first + 3});
            });
  return mesh;
}

std::vector<double> ring_strain(const RingFrame& frame, const Weave& weave) {
  const int n = std::min(frame.size(), weave.size());
  std::vector<double> strain(n, 0.0);
  for (int ring = 0; ring < n; ++ring) {
    double sum = 0.0;
    int count = 0;
    for (const int other : weave.neighbours[ring]) {
      if (other < 0 || other >= n) continue;
      const double rest = (weave.rest_position.col(other) - weave.rest_position.col(ring)).norm();
      const double now = (frame.position.col(other) - frame.position.col(ring)).norm();
      if (!(rest > 0.0) || !std::isfinite(now)) continue;
      sum += now / rest - 1.0;
      ++count;
    }
    strain[ring] = count > 0 ? sum / count : 0.0;
  }
  return strain;
}

Mesh cloth_mesh(const RingFrame& frame, const Weave& weave, int subdivisions,
                const Vector3d& origin) {
  Mesh mesh;
  mesh.stride = 9;
  const int n = std::min(frame.size(), weave.size());
  const int s = std::max(subdivisions, 1);

  // quads (i, j), (i+1, j), (i+1, j+1), (i, j+1) wherever all four rings exist and are finite
  std::vector<std::array<int, 4>> quads;
  auto usable = [&](int ring) {
    return ring >= 0 && ring < n && frame.position.col(ring).allFinite();
  };
  for (int ring = 0; ring < n; ++ring) {
    const int right = weave.neighbours[ring][1], above = weave.neighbours[ring][3];
    const int diagonal = right >= 0 ? weave.neighbours[right][3] : -1;
    if (usable(ring) && usable(right) && usable(diagonal) && usable(above)) {
      quads.push_back({ring, right, diagonal, above});
    }
  }

  // area-weighted vertex normals from the two triangles of every quad
  std::vector<Vector3d> normals(n, Vector3d::Zero());
  for (const auto& q : quads) {
    for (const auto& tri : {std::array<int, 3>{q[0], q[1], q[2]}, {q[0], q[2], q[3]}}) {
      const Vector3d a = frame.position.col(tri[0]), b = frame.position.col(tri[1]),
                     c = frame.position.col(tri[2]);
      const Vector3d face = (b - a).cross(c - a);
      for (int v : tri) normals[v] += face;
    }
  }
  for (Vector3d& normal : normals) {
    normal = normal.norm() > 0 ? normal.normalized() : Vector3d::UnitY();
  }

  const std::vector<double> strain = ring_strain(frame, weave);
  // each quad becomes s x s bilinear quads (s = 1: the plain ring-centre mesh)
  for (const auto& q : quads) {
    const auto first = static_cast<std::uint32_t>(mesh.vertex_count());
    for (int y = 0; y <= s; ++y) {
      for (int x = 0; x <= s; ++x) {
        const double fx = static_cast<double>(x) / s, fy = static_cast<double>(y) / s;
        const double w[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), fx * fy, (1 - fx) * fy};
        Vector3d p = Vector3d::Zero(), nrm = Vector3d::Zero();
        double ui = 0, uj = 0, e = 0;
        for (int k = 0; k < 4; ++k) {
          p += w[k] * frame.position.col(q[k]);
          nrm += w[k] * normals[q[k]];
          ui += w[k] * weave.grid[q[k]][0];
          uj += w[k] * weave.grid[q[k]][1];
          e += w[k] * strain[q[k]];
        }
        push(mesh.vertices, p - origin);
        push(mesh.vertices, nrm.norm() > 0 ? nrm.normalized() : Vector3d::UnitY());
        mesh.vertices.push_back(static_cast<float>(ui));
        mesh.vertices.push_back(static_cast<float>(uj));
        mesh.vertices.push_back(static_cast<float>(e));
      }
    }
    for (int y = 0; y < s; ++y) {
      for (int x = 0; x < s; ++x) {
        const std::uint32_t a = first + y * (s + 1) + x, b = a + 1, d = a + s + 1, c = d + 1;
        mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
      }
    }
  }
  return mesh;
}

Mesh scene_mesh(const Scene& scene, const Vector3d& origin, const Vector3d& focus, double extent) {
  SceneMeshBuilder b;
  b.origin = origin;
  for (const Collider& collider : scene.colliders) {
    switch (collider.type) {
      case Collider::Type::plane: {
        // a finite square of the plane around the point nearest the fabric, checkered
        const Vector3d n = collider.normal.normalized();
        const Vector3d center = focus - n * n.dot(focus - collider.center);
        Vector3d t1, t2;
        tangents(n, t1, t2);
        t1 *= extent, t2 *= extent;
        b.color = {0.56, 0.56, 0.53, 1.0};
        b.quad(center - t1 - t2, center + t1 - t2, center + t1 + t2, center - t1 + t2, n);
        break;
      }
      case Collider::Type::sphere:
        b.color = {0.62, 0.42, 0.36, 0.0};
        add_sphere(b, collider.center, collider.radius);
        break;
      case Collider::Type::box:
        b.color = {0.42, 0.48, 0.6, 0.0};
        add_box(b, collider.center, collider.half_extents);
        break;
      case Collider::Type::cylinder:
        b.color = {0.48, 0.56, 0.44, 0.0};
        add_cylinder(b, collider.center, collider.radius, collider.half_height);
        break;
    }
  }
  if (scene.support) {
    // the drape table: a thin disk whose top is the support's centre height, lifted by a hair
    // (far below a wire's radius, far above the depth buffer's resolution) so that it never
    // shares a plane with the top of a collider it rests on and fights it for depth
    const double thickness = 0.02 * scene.support->radius, lift = 1e-3 * scene.support->radius;
    b.color = {0.52, 0.4, 0.28, 0.0};
    add_cylinder(b, scene.support->center + Vector3d(0.0, lift - 0.5 * thickness, 0.0),
                 scene.support->radius, 0.5 * thickness);
  }
  return b.mesh;
}

}  // namespace chainmail::render
