#include "tear/geometry/codim_mesh.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

namespace tear {

CodimMesh make_sheet(const Vec3d& center, const double size[2], const int resolution[2],
                     bool random, uint64_t seed) {
  CodimMesh mesh;
  mesh.manifold = 2;
  const int nx = resolution[0], nz = resolution[1];
  const double hx = size[0] / nx, hz = size[1] / nz;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.25, 0.25);
  auto index = [&](int i, int k) { return uint32_t(k * (nx + 1) + i); };
  for (int k = 0; k <= nz; ++k)
    for (int i = 0; i <= nx; ++i) {
      double u = i, w = k;
      if (random && i > 0 && i < nx && k > 0 && k < nz) u += jitter(rng), w += jitter(rng);
      mesh.vertices.push_back(center + Vec3d(-size[0] / 2 + u * hx, 0, -size[1] / 2 + w * hz));
    }
  std::bernoulli_distribution coin(0.5);
  for (int k = 0; k < nz; ++k)
    for (int i = 0; i < nx; ++i) {
      const uint32_t a = index(i, k), b = index(i + 1, k), c = index(i + 1, k + 1),
                     d = index(i, k + 1);
      // Counter-clockwise seen from +y (x, z axes): normals point up.
      const bool diagonal_ac = random ? coin(rng) : (i + k) % 2 == 0;
      if (diagonal_ac) {
        mesh.elements.push_back({a, c, b});
        mesh.elements.push_back({a, d, c});
      } else {
        mesh.elements.push_back({a, d, b});
        mesh.elements.push_back({b, d, c});
      }
    }
  return mesh;
}

CodimMesh make_rope(const Vec3d& from, const Vec3d& to, int segments) {
  CodimMesh mesh;
  mesh.manifold = 1;
  for (int k = 0; k <= segments; ++k)
    mesh.vertices.push_back(from + (to - from) * (double(k) / segments));
  for (int k = 0; k < segments; ++k) mesh.elements.push_back({uint32_t(k), uint32_t(k + 1), 0});
  return mesh;
}

CodimMesh make_knit(const Vec3d& center, const double size[2], int wales, int courses,
                    int segments_per_loop) {
  constexpr double kPi = 3.14159265358979323846;
  CodimMesh mesh;
  mesh.manifold = 1;
  const double W = size[0] / wales, H = size[1] / courses, depth = 0.25 * std::min(W, H);
  const int per_course = wales * segments_per_loop;
  auto at = [&](int j, int i) -> Vec3d {
    const double t = 2 * kPi * i / segments_per_loop;
    return center + Vec3d(W * (t + 0.9 * std::sin(2 * t)) / (2 * kPi) - size[0] / 2,
                          H * (j - (courses - 1) / 2.0 + 0.75 * std::cos(t)),
                          depth * std::cos(2 * t));
  };
  for (int j = 0; j < courses; ++j) {
    // Odd courses run back (flat knitting): the same loops, the yarn the other way.
    for (int k = 0; k <= per_course; ++k) mesh.vertices.push_back(at(j, j % 2 == 0 ? k : per_course - k));
    if (j + 1 == courses) break;
    // Up the swatch's side to the next course, in segments about as long as the loops'.
    const Vec3d from = mesh.vertices.back(), to = at(j + 1, j % 2 == 0 ? per_course : 0);
    const double step = (at(j, 1) - at(j, 0)).norm();
    const int n = std::max(1, int(std::ceil((to - from).norm() / step)));
    for (int k = 1; k < n; ++k) mesh.vertices.push_back(from + (to - from) * (double(k) / n));
  }
  for (uint32_t v = 0; v + 1 < mesh.vertices.size(); ++v) mesh.elements.push_back({v, v + 1, 0});
  return mesh;
}

CodimMesh make_strands(const Vec3d& center, double radius, const Vec3d& direction, double cap_deg,
                       int count, double length, int segments, int dim) {
  constexpr double kPi = 3.14159265358979323846;
  CodimMesh mesh;
  mesh.manifold = 1;
  const Vec3d up = direction.normalized();
  // Two unit vectors across `up` (2D: the one in the plane).
  Vec3d side = dim == 2 ? Vec3d(-up.y(), up.x(), 0)
                        : (std::abs(up.x()) < 0.9 ? Vec3d::UnitX() : Vec3d::UnitY()).cross(up).normalized();
  const Vec3d other = up.cross(side);
  const double cap = cap_deg * kPi / 180;
  const double golden = kPi * (3 - std::sqrt(5.0));
  for (int k = 0; k < count; ++k) {
    Vec3d n;
    if (dim == 2) {
      const double a = count == 1 ? 0 : -cap + 2 * cap * k / (count - 1);
      n = std::cos(a) * up + std::sin(a) * side;
    } else {
      const double c = 1 - (1 - std::cos(cap)) * (k + 0.5) / count;
      const double s = std::sqrt(std::max(0.0, 1 - c * c)), phi = golden * k;
      n = c * up + s * (std::cos(phi) * side + std::sin(phi) * other);
    }
    const uint32_t first = uint32_t(mesh.vertices.size());
    for (int j = 0; j <= segments; ++j)
      mesh.vertices.push_back(center + (radius + length * j / segments) * n);
    for (int j = 0; j < segments; ++j)
      mesh.elements.push_back({first + uint32_t(j), first + uint32_t(j + 1), 0});
  }
  if (dim == 2)
    for (Vec3d& v : mesh.vertices) v.z() = 0;
  return mesh;
}

std::string find_mesh_defect(const CodimMesh& mesh, int dim) {
  const char* what = mesh.manifold == 1 ? "segment " : "triangle ";
  const size_t n = mesh.vertices.size(), corners = mesh.corners();
  if (mesh.elements.empty())
    return std::string("has no ") + (mesh.manifold == 1 ? "segments" : "triangles");
  auto point = [&](size_t v) {
    const Vec3d& x = mesh.vertices[v];
    char s[96];
    std::snprintf(s, sizeof s, "(%.6g, %.6g, %.6g)", x[0], x[1], x[2]);
    return std::string(s);
  };
  Vec3d lo = Vec3d::Constant(INFINITY), hi = Vec3d::Constant(-INFINITY);
  for (size_t v = 0; v < n; ++v) {
    if (!mesh.vertices[v].allFinite()) return "vertex " + std::to_string(v) + " is not finite";
    if (dim == 2 && mesh.vertices[v].z() != 0)
      return "vertex " + std::to_string(v) + " " + point(v) + " is off the plane z = 0 of a 2D scene";
    lo = lo.cwiseMin(mesh.vertices[v]);
    hi = hi.cwiseMax(mesh.vertices[v]);
  }
  // Two vertices at one point (a seam not welded, a duplicated strand): sorted, neighbours.
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  auto key = [&](uint32_t v) {
    const Vec3d& x = mesh.vertices[v];
    return std::array<double, 3>{x[0], x[1], x[2]};
  };
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return key(a) != key(b) ? key(a) < key(b) : a < b;
  });
  for (size_t k = 1; k < n; ++k)
    if (key(order[k]) == key(order[k - 1]))
      return "vertices " + std::to_string(order[k - 1]) + " and " + std::to_string(order[k]) +
             " are at the same point " + point(order[k]) + " (weld them into one)";
  const double scale = std::max((hi - lo).maxCoeff(), 1e-300);
  std::vector<char> used(n, 0);
  for (size_t e = 0; e < mesh.elements.size(); ++e) {
    const std::array<uint32_t, 3>& el = mesh.elements[e];
    std::string ids;
    for (size_t c = 0; c < corners; ++c) ids += (c ? ", " : "") + std::to_string(el[c]);
    const std::string name = what + std::to_string(e);
    for (size_t c = 0; c < corners; ++c)
      if (el[c] >= n)
        return name + " uses vertex " + std::to_string(el[c]) + ", beyond the last (" +
               std::to_string(n == 0 ? 0 : n - 1) + ")";
    for (size_t c = 0; c < corners; ++c)
      for (size_t d = c + 1; d < corners; ++d)
        if (el[c] == el[d]) return name + " uses vertex " + std::to_string(el[c]) + " twice";
    const Vec3d e1 = mesh.vertices[el[1]] - mesh.vertices[el[0]];
    // Relative to the mesh's extent: 1e-12 of it is below any meaningful element.
    if (mesh.manifold == 1) {
      if (!(e1.norm() > 1e-12 * scale)) return name + " has zero length (vertices " + ids + ")";
    } else {
      const Vec3d e2 = mesh.vertices[el[2]] - mesh.vertices[el[0]];
      if (!(e1.cross(e2).norm() > 1e-12 * scale * scale))
        return name + " has zero area (vertices " + ids + ")";
    }
    for (size_t c = 0; c < corners; ++c) used[el[c]] = 1;
  }
  for (size_t v = 0; v < n; ++v)
    if (!used[v])
      return "vertex " + std::to_string(v) + " " + point(v) + " belongs to no " +
             (mesh.manifold == 1 ? "segment" : "triangle");
  return "";
}

}  // namespace tear
