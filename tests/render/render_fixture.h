// Frames, looks and colour checks for the renderer's tests.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "tear/io/point_table.h"
#include "tear/render/render.h"

namespace tear::test {

// A frame with every column the colour maps read; `scalar` is both driving_force and
// damage_laplacian (0 when empty).
inline PointTable make_frame(const std::vector<Eigen::Vector3d>& x,
                             const std::vector<double>& damage,
                             const std::vector<Eigen::Vector3d>& v = {},
                             const std::vector<double>& scalar = {}) {
  PointTable t;
  t.count = x.size();
  std::vector<double> id(x.size()), c[3], vc[3], mat(x.size()), f[3];
  for (size_t i = 0; i < x.size(); ++i) {
    id[i] = double(i);
    mat[i] = double(i % 2);
    for (int a = 0; a < 3; ++a) {
      c[a].push_back(x[i][a]);
      vc[a].push_back(v.empty() ? 0.0 : v[i][a]);
      f[a].push_back(a == 0 ? 1.0 : 0.0);
    }
  }
  t.add("id", ColumnType::Int32, id);
  const char* xs[3] = {"x", "y", "z"};
  const char* vs[3] = {"vx", "vy", "vz"};
  const char* fs[3] = {"fx", "fy", "fz"};
  for (int a = 0; a < 3; ++a) t.add(xs[a], ColumnType::Float32, c[a]);
  for (int a = 0; a < 3; ++a) t.add(vs[a], ColumnType::Float32, vc[a]);
  t.add("damage", ColumnType::Float32, damage);
  t.add("material", ColumnType::UInt8, mat);
  for (int a = 0; a < 3; ++a) t.add(fs[a], ColumnType::Float32, f[a]);
  // The optional columns: the same values (default 0) for both.
  const std::vector<double> extra = scalar.empty() ? std::vector<double>(x.size(), 0) : scalar;
  t.add("driving_force", ColumnType::Float32, extra);
  t.add("damage_laplacian", ColumnType::Float32, extra);
  return t;
}

inline RenderLook look_for(int dim, double radius) {
  RenderLook look;
  look.dim = dim;
  look.radius = radius;
  look.spacing = 2 * radius;
  look.material_names = {"meat", "bone"};
  return look;
}

// Hue in degrees of an 8-bit colour.
inline double hue(const uint8_t* p) {
  const double r = p[0], g = p[1], b = p[2];
  const double mx = std::max({r, g, b}), mn = std::min({r, g, b});
  if (mx == mn) return 0;
  double h;
  if (mx == r)
    h = std::fmod((g - b) / (mx - mn), 6.0);
  else if (mx == g)
    h = (b - r) / (mx - mn) + 2;
  else
    h = (r - g) / (mx - mn) + 4;
  h *= 60;
  return h < 0 ? h + 360 : h;
}

}  // namespace tear::test
