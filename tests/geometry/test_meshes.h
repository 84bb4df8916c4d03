// Closed triangle meshes for the mesh tests (geometry/, io/, scene/): a box and a torus, made
// here so that no test needs a file from elsewhere.
#pragma once

#include "tear/io/mesh_io.h"
#include "tear/math/types.h"

#include <array>
#include <cmath>
#include <vector>

namespace tear::test {

struct TestMesh {
  std::vector<Vec3d> vertices;
  std::vector<std::array<int, 3>> triangles;  // outward (counter-clockwise seen from outside)
};

// The box [lo, hi] as 12 triangles on 8 vertices.
inline TestMesh box_mesh(const Vec3d& lo, const Vec3d& hi) {
  TestMesh m;
  for (int c = 0; c < 8; ++c)
    m.vertices.emplace_back((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(),
                            (c & 4) ? hi.z() : lo.z());
  // Faces as quads (corner bits: 1 = +x, 2 = +y, 4 = +z), counter-clockwise from outside.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  return m;
}

// A torus about the z axis through `center`: tube centre radius R, tube radius r, nu segments
// around z and nv around the tube. Its exact volume is 2 pi^2 R r^2; the mesh's is a little less.
inline TestMesh torus_mesh(const Vec3d& center, double R, double r, int nu, int nv) {
  constexpr double kPi = 3.14159265358979323846;
  TestMesh m;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * kPi * i / nu, v = 2 * kPi * j / nv;
      m.vertices.push_back(center + Vec3d((R + r * std::cos(v)) * std::cos(u),
                                          (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)));
    }
  auto id = [&](int i, int j) { return (i % nu) * nv + (j % nv); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      m.triangles.push_back({a, b, c});
      m.triangles.push_back({a, c, d});
    }
  return m;
}

// As io/ stores meshes (float vertices), for writing test files.
inline TriMesh to_trimesh(const TestMesh& m) {
  TriMesh t;
  for (const Vec3d& v : m.vertices) t.vertices.push_back(v.cast<float>());
  for (const auto& tri : m.triangles) t.triangles.push_back({tri[0], tri[1], tri[2]});
  return t;
}

}  // namespace tear::test
