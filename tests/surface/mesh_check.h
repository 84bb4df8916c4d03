// Topology and enclosed volume of a triangle mesh, for the surface tests.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <numeric>
#include <utility>
#include <vector>

#include "tear/io/mesh_io.h"

namespace tear {

struct MeshCheck {
  bool closed = true;    // every edge in exactly two triangles
  bool oriented = true;  // ... once in each direction (consistent orientation)
  bool manifold = true;  // the triangles around each vertex form a single fan
  int components = 0;    // connected by shared vertices
  double volume = 0;     // divergence theorem: sum of (a . (b x c)) / 6; > 0 when outward
};

inline MeshCheck check_mesh(const TriMesh& m) {
  MeshCheck c;
  auto corner = [&](const std::array<int32_t, 3>& t, int e) { return t[size_t(e % 3)]; };
  std::map<std::pair<int32_t, int32_t>, int> directed;
  for (const auto& t : m.triangles)
    for (int e = 0; e < 3; ++e) ++directed[{corner(t, e), corner(t, e + 1)}];
  for (const auto& [edge, n] : directed) {
    const auto back = directed.find({edge.second, edge.first});
    const int n_back = back == directed.end() ? 0 : back->second;
    if (n + n_back != 2) c.closed = false;
    if (n != 1 || n_back != 1) c.oriented = false;
  }
  // The link of a vertex (the edge opposite it in each of its triangles) must be one cycle.
  std::vector<std::map<int32_t, int32_t>> link(m.vertices.size());
  for (const auto& t : m.triangles)
    for (int e = 0; e < 3; ++e)
      if (!link[size_t(corner(t, e))].emplace(corner(t, e + 1), corner(t, e + 2)).second)
        c.manifold = false;
  for (const auto& next : link) {
    if (next.empty()) continue;
    int32_t v = next.begin()->first;
    size_t steps = 0;
    do {
      const auto it = next.find(v);
      if (it == next.end()) break;
      v = it->second;
      ++steps;
    } while (v != next.begin()->first && steps <= next.size());
    if (steps != next.size() || v != next.begin()->first) c.manifold = false;
  }
  std::vector<int32_t> parent(m.vertices.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int32_t v) {
    while (parent[size_t(v)] != v) v = parent[size_t(v)] = parent[size_t(parent[size_t(v)])];
    return v;
  };
  std::vector<bool> used(m.vertices.size(), false);
  for (const auto& t : m.triangles) {
    for (int32_t v : t) used[size_t(v)] = true;
    parent[size_t(root(t[1]))] = root(t[0]);
    parent[size_t(root(t[2]))] = root(t[0]);
  }
  for (size_t v = 0; v < m.vertices.size(); ++v)
    c.components += used[v] && root(int32_t(v)) == int32_t(v);
  for (const auto& t : m.triangles) {
    const Eigen::Vector3d a = m.vertices[size_t(t[0])].cast<double>();
    const Eigen::Vector3d b = m.vertices[size_t(t[1])].cast<double>();
    const Eigen::Vector3d d = m.vertices[size_t(t[2])].cast<double>();
    c.volume += a.dot(b.cross(d)) / 6;
  }
  return c;
}

}  // namespace tear
