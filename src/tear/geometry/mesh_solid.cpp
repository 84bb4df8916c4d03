#include "tear/geometry/mesh_solid.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <utility>

namespace tear {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kLeafSize = 8;

std::string point_str(const Vec3d& p) {
  std::ostringstream s;
  s.precision(9);
  s << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return s.str();
}

[[noreturn]] void fail(const std::string& why) { throw std::runtime_error(why); }

// The point of triangle (a, b, c) nearest to p (Ericson, Real-Time Collision Detection, 5.1.5:
// the Voronoi region of p among the triangle's vertices, edges and face).
Vec3d closest_on_triangle(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c) {
  const Vec3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1 / (va + vb + vc);
  return a + (vb * denom) * ab + (vc * denom) * ac;
}

double box_distance2(const Vec3d& p, const Vec3d& lo, const Vec3d& hi) {
  return (lo - p).cwiseMax(p - hi).cwiseMax(0.0).squaredNorm();
}

}  // namespace

MeshSolid::MeshSolid(const std::vector<Vec3d>& vertices, const std::vector<Tri>& triangles,
                     std::string name)
    : name_(std::move(name)) {
  if (triangles.empty()) fail("has no triangles");
  const int n = int(vertices.size());
  for (int v = 0; v < n; ++v)
    if (!vertices[size_t(v)].allFinite())
      fail("vertex " + std::to_string(v) + " is not finite " + point_str(vertices[size_t(v)]));
  for (size_t t = 0; t < triangles.size(); ++t)
    for (int i : triangles[t])
      if (i < 0 || i >= n)
        fail("triangle " + std::to_string(t) + " has vertex index " + std::to_string(i) +
             ", but there are " + std::to_string(n) + " vertices");

  // Merge vertices with equal coordinates (OBJ files split vertices at texture seams, STL
  // repeats them for every triangle).
  std::vector<int> by_position(static_cast<size_t>(n)), merged(static_cast<size_t>(n));
  std::iota(by_position.begin(), by_position.end(), 0);
  auto less = [&](int a, int b) {
    const Vec3d &x = vertices[size_t(a)], &y = vertices[size_t(b)];
    return std::tie(x.x(), x.y(), x.z()) < std::tie(y.x(), y.y(), y.z());
  };
  std::sort(by_position.begin(), by_position.end(), [&](int a, int b) {
    return less(a, b) || (!less(b, a) && a < b);
  });
  for (size_t k = 0; k < by_position.size(); ++k) {
    const int v = by_position[k];
    if (k > 0 && !less(by_position[k - 1], v)) {
      merged[size_t(v)] = merged[size_t(by_position[k - 1])];
    } else {
      merged[size_t(v)] = int(vertices_.size());
      vertices_.push_back(vertices[size_t(v)]);
    }
  }
  // Triangles with a repeated corner have no area and no boundary of their own: dropped.
  std::vector<size_t> source;  // input number of each kept triangle, for messages
  for (size_t t = 0; t < triangles.size(); ++t) {
    const Tri m = {merged[size_t(triangles[t][0])], merged[size_t(triangles[t][1])],
                   merged[size_t(triangles[t][2])]};
    if (m[0] == m[1] || m[1] == m[2] || m[2] == m[0]) continue;
    triangles_.push_back(m);
    source.push_back(t);
  }
  if (triangles_.empty()) fail("has no triangles of non-zero size");

  // Closed and consistently oriented: every edge is run along once in each direction, by two
  // triangles. Edges sorted by their (low, high) vertices, direction and triangle.
  struct Edge {
    int lo, hi;
    bool forward;  // runs from lo to hi
    size_t triangle;
  };
  std::vector<Edge> edges;
  edges.reserve(3 * triangles_.size());
  for (size_t t = 0; t < triangles_.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = triangles_[t][size_t(k)], b = triangles_[t][size_t((k + 1) % 3)];
      edges.push_back({std::min(a, b), std::max(a, b), a < b, source[t]});
    }
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
    return std::tie(x.lo, x.hi, x.forward, x.triangle) < std::tie(y.lo, y.hi, y.forward, y.triangle);
  });
  size_t open = 0;
  const Edge* first_open = nullptr;
  for (size_t k = 0; k < edges.size();) {
    size_t e = k + 1;
    while (e < edges.size() && edges[e].lo == edges[k].lo && edges[e].hi == edges[k].hi) ++e;
    const std::string between = "the edge between vertices " + std::to_string(edges[k].lo) +
                                " " + point_str(vertices_[size_t(edges[k].lo)]) + " and " +
                                std::to_string(edges[k].hi) + " " +
                                point_str(vertices_[size_t(edges[k].hi)]);
    if (e - k == 1) {
      if (!first_open) first_open = &edges[k];
      ++open;
    } else if (e - k > 2) {
      fail("is not a manifold: " + between + " is shared by " + std::to_string(e - k) +
           " triangles");
    } else if (edges[k].forward == edges[k + 1].forward) {
      fail("is not consistently oriented: triangles " + std::to_string(edges[k].triangle) +
           " and " + std::to_string(edges[k + 1].triangle) + " both run the same way along " +
           between + " (one of them faces the wrong way)");
    }
    k = e;
  }
  if (first_open)
    fail("is not closed: " + std::to_string(open) + " edge(s) belong to one triangle only, e.g. " +
         "the edge between vertices " + std::to_string(first_open->lo) + " " +
         point_str(vertices_[size_t(first_open->lo)]) + " and " + std::to_string(first_open->hi) +
         " " + point_str(vertices_[size_t(first_open->hi)]) + " of triangle " +
         std::to_string(first_open->triangle));

  // Enclosed volume (divergence theorem, about the bounds' centre for rounding); an inward
  // oriented surface is turned inside out.
  Vec3d lo = vertices_[0], hi = vertices_[0];
  for (const Vec3d& v : vertices_) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  const Vec3d mid = 0.5 * (lo + hi);
  for (const Tri& t : triangles_)
    volume_ += (vertices_[size_t(t[0])] - mid)
                   .dot((vertices_[size_t(t[1])] - mid).cross(vertices_[size_t(t[2])] - mid)) /
               6;
  const double extent = (hi - lo).maxCoeff();
  if (!(std::abs(volume_) > 1e-12 * extent * extent * extent))
    fail("encloses no volume (it is flat or its parts cancel)");
  if (volume_ < 0) {
    for (Tri& t : triangles_) std::swap(t[1], t[2]);
    volume_ = -volume_;
    turned_ = true;
  }
  nodes_.reserve(2 * triangles_.size() / kLeafSize + 2);
  build(0, int(triangles_.size()));
  classify_voxels();
}

void MeshSolid::classify_voxels() {
  constexpr int kVoxels = 128;  // along the longest axis of the bounds
  const Vec3d extent = hi() - lo();
  voxel_h_ = extent.maxCoeff() / kVoxels;
  voxel_lo_ = lo() - Vec3d::Constant(voxel_h_);
  for (int d = 0; d < 3; ++d) voxel_n_[size_t(d)] = int(std::ceil(extent[d] / voxel_h_)) + 2;
  const size_t nx = size_t(voxel_n_[0]), ny = size_t(voxel_n_[1]), nz = size_t(voxel_n_[2]);
  voxels_.assign(nx * ny * nz, kOut);
  // Voxels that a triangle may touch: in its box (widened against rounding) and crossed by its
  // plane (the plane test of Akenine-Moller's triangle-box overlap; conservative).
  const double eps = 1e-9 * extent.maxCoeff();
  auto cell = [&](double x, int d) {
    return std::clamp(int(std::floor((x - voxel_lo_[d]) / voxel_h_)), 0, voxel_n_[size_t(d)] - 1);
  };
  for (const Tri& t : triangles_) {
    Vec3d a = vertices_[size_t(t[0])], b = a;
    for (int v : t) a = a.cwiseMin(vertices_[size_t(v)]), b = b.cwiseMax(vertices_[size_t(v)]);
    const int x0 = cell(a.x() - eps, 0), x1 = cell(b.x() + eps, 0), y0 = cell(a.y() - eps, 1),
              y1 = cell(b.y() + eps, 1), z0 = cell(a.z() - eps, 2), z1 = cell(b.z() + eps, 2);
    const Vec3d& p0 = vertices_[size_t(t[0])];
    const Vec3d normal = (vertices_[size_t(t[1])] - p0).cross(vertices_[size_t(t[2])] - p0);
    const double reach = 0.5 * voxel_h_ * normal.cwiseAbs().sum() * (1 + 1e-9) + eps * normal.norm();
    for (int z = z0; z <= z1; ++z)
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const Vec3d centre = voxel_lo_ + voxel_h_ * Vec3d(x + 0.5, y + 0.5, z + 0.5);
          if (std::abs(normal.dot(centre - p0)) <= reach)
            voxels_[(size_t(z) * ny + size_t(y)) * nx + size_t(x)] = kExact;
        }
  }
  // Connected regions of the other voxels (across faces): the segment between two
  // neighbours' centres stays in their closed union, which no triangle touches, so the
  // winding number is the same at both. One exact evaluation per region.
  std::vector<int> region(voxels_.size(), -1);
  std::vector<size_t> queue;
  for (size_t seed = 0; seed < voxels_.size(); ++seed) {
    if (voxels_[seed] == kExact || region[seed] >= 0) continue;
    const Vec3d centre = voxel_lo_ + voxel_h_ * Vec3d(double(seed % nx) + 0.5,
                                                      double(seed / nx % ny) + 0.5,
                                                      double(seed / nx / ny) + 0.5);
    bool on_surface = false;
    const double w = winding(centre, &on_surface);
    const uint8_t state = w > -0.5 && w < 0.5 ? kOut : w >= 0.5 && w < 1.5 ? kIn : kExact;
    queue.assign(1, seed);
    region[seed] = int(seed);
    while (!queue.empty()) {
      const size_t v = queue.back();
      queue.pop_back();
      voxels_[v] = state;
      const size_t x = v % nx, y = v / nx % ny, z = v / nx / ny;
      const size_t next[6] = {x > 0 ? v - 1 : v,           x + 1 < nx ? v + 1 : v,
                              y > 0 ? v - nx : v,          y + 1 < ny ? v + nx : v,
                              z > 0 ? v - nx * ny : v,     z + 1 < nz ? v + nx * ny : v};
      for (size_t u : next)
        if (region[u] < 0 && voxels_[u] != kExact) region[u] = int(seed), queue.push_back(u);
    }
  }
}

// The subtree of triangles_[begin, end): its box, then either a leaf or the two halves split
// at the median centroid along the box's longest axis. Returns the node's index.
int MeshSolid::build(int begin, int end) {
  const int index = int(nodes_.size());
  nodes_.emplace_back();
  Node node;
  node.begin = begin, node.end = end;
  node.lo = Vec3d::Constant(std::numeric_limits<double>::infinity());
  node.hi = -node.lo;
  for (int t = begin; t < end; ++t)
    for (int v : triangles_[size_t(t)])
      node.lo = node.lo.cwiseMin(vertices_[size_t(v)]), node.hi = node.hi.cwiseMax(vertices_[size_t(v)]);
  make_cap(&node);
  if (end - begin > kLeafSize) {
    int axis = 0;
    (node.hi - node.lo).maxCoeff(&axis);
    auto centroid = [&](const Tri& t) {
      return vertices_[size_t(t[0])][axis] + vertices_[size_t(t[1])][axis] +
             vertices_[size_t(t[2])][axis];
    };
    const int mid = begin + (end - begin) / 2;
    std::nth_element(triangles_.begin() + begin, triangles_.begin() + mid,
                     triangles_.begin() + end, [&](const Tri& a, const Tri& b) {
                       const double ca = centroid(a), cb = centroid(b);
                       return ca < cb || (ca == cb && a < b);
                     });
    node.left = build(begin, mid);
    node.right = build(mid, end);
  }
  nodes_[size_t(index)] = node;
  return index;
}

// The fan from one boundary vertex over the subtree's boundary edges (those whose reverse is
// not in the subtree), kept only where it has fewer triangles than the subtree.
void MeshSolid::make_cap(Node* node) {
  std::vector<std::pair<int, int>> edges;
  for (int t = node->begin; t < node->end; ++t)
    for (int k = 0; k < 3; ++k)
      edges.emplace_back(triangles_[size_t(t)][size_t(k)], triangles_[size_t(t)][size_t((k + 1) % 3)]);
  std::sort(edges.begin(), edges.end());
  std::vector<Tri> fan;
  int apex = -1;
  for (const auto& [a, b] : edges) {
    if (std::binary_search(edges.begin(), edges.end(), std::make_pair(b, a))) continue;
    if (apex < 0) apex = a;
    if (a != apex && b != apex) fan.push_back({apex, a, b});
  }
  if (fan.size() >= size_t(node->end - node->begin)) return;  // no cap: node->cap_end < begin
  node->cap_begin = int(caps_.size());
  caps_.insert(caps_.end(), fan.begin(), fan.end());
  node->cap_end = int(caps_.size());
}

// Signed solid angle of triangle t seen from p (Van Oosterom & Strackee 1983); sets
// *on_surface where p lies on the closed triangle up to rounding (in its plane: det = 0; within
// it: den < 0, on an edge or a corner den = 0), relative to |a| |b| |c|.
double MeshSolid::solid_angle(const Tri& t, const Vec3d& p, bool* on_surface) const {
  const Vec3d a = vertices_[size_t(t[0])] - p, b = vertices_[size_t(t[1])] - p,
              c = vertices_[size_t(t[2])] - p;
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double det = a.dot(b.cross(c));
  const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
  const double tol = 1e-12 * la * lb * lc;
  if (std::abs(det) <= tol && den <= tol) *on_surface = true;
  return 2 * std::atan2(det, den);
}

double MeshSolid::winding(const Vec3d& p, bool* on_surface) const {
  // A point on a box's face counts as inside it (the fan's argument needs p off the hull).
  const double eps = 1e-9 * (hi() - lo()).maxCoeff();
  double sum = 0;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[size_t(stack[--top])];
    const bool outside = ((n.lo.array() - eps) > p.array()).any() ||
                         ((n.hi.array() + eps) < p.array()).any();
    if (outside && n.cap_end >= n.cap_begin) {
      for (int c = n.cap_begin; c < n.cap_end; ++c)
        sum += solid_angle(caps_[size_t(c)], p, on_surface);
    } else if (n.left < 0) {
      for (int t = n.begin; t < n.end; ++t)
        sum += solid_angle(triangles_[size_t(t)], p, on_surface);
    } else {
      stack[top++] = n.left;
      stack[top++] = n.right;
    }
  }
  return sum / (4 * kPi);
}

double MeshSolid::winding_number(const Vec3d& p) const {
  bool on_surface = false;
  return winding(p, &on_surface);
}

bool MeshSolid::inside(const Vec3d& p) const {
  size_t v = 0, stride = 1;
  for (int d = 0; d < 3; ++d) {
    const double c = std::floor((p[d] - voxel_lo_[d]) / voxel_h_);
    if (!(c >= 0 && c < voxel_n_[size_t(d)])) return false;  // beyond the bounds (or NaN)
    v += size_t(c) * stride, stride *= size_t(voxel_n_[size_t(d)]);
  }
  if (voxels_[v] != kExact) return voxels_[v] == kIn;
  bool on_surface = false;
  const double w = winding(p, &on_surface);
  if (on_surface) return true;
  if (w >= 1.5 || w <= -0.5) {
    std::ostringstream s;
    s.precision(3);
    s << w;
    fail(name_ + " winds " + s.str() + " times around " + point_str(p) +
         ": the surface crosses itself or has overlapping shells there");
  }
  return w >= 0.5;
}

double MeshSolid::closest(const Vec3d& p, Vec3d* nearest, int* triangle) const {
  double best = std::numeric_limits<double>::infinity();
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[size_t(stack[--top])];
    if (box_distance2(p, n.lo, n.hi) >= best) continue;
    if (n.left < 0) {
      for (int t = n.begin; t < n.end; ++t) {
        const Tri& tri = triangles_[size_t(t)];
        const Vec3d q = closest_on_triangle(p, vertices_[size_t(tri[0])],
                                            vertices_[size_t(tri[1])], vertices_[size_t(tri[2])]);
        const double d2 = (q - p).squaredNorm();
        if (d2 < best) best = d2, *nearest = q, *triangle = t;
      }
      continue;
    }
    // The nearer child last, so that it is visited first.
    const Node &l = nodes_[size_t(n.left)], &r = nodes_[size_t(n.right)];
    const bool left_first = box_distance2(p, l.lo, l.hi) <= box_distance2(p, r.lo, r.hi);
    stack[top++] = left_first ? n.right : n.left;
    stack[top++] = left_first ? n.left : n.right;
  }
  return std::sqrt(best);
}

double MeshSolid::distance(const Vec3d& p) const {
  Vec3d q;
  int t = 0;
  return closest(p, &q, &t);
}

Vec3d MeshSolid::normal(const Vec3d& p) const {
  Vec3d q;
  int t = 0;
  const double d = closest(p, &q, &t);
  const Tri& tri = triangles_[size_t(t)];
  const Vec3d face = (vertices_[size_t(tri[1])] - vertices_[size_t(tri[0])])
                         .cross(vertices_[size_t(tri[2])] - vertices_[size_t(tri[0])])
                         .normalized();
  // On (or within rounding of) the surface the direction to it is lost: the face's normal.
  if (d <= 1e-12 * (hi() - lo()).maxCoeff()) return face;
  return (inside(p) ? q - p : p - q) / d;
}

}  // namespace tear
