#include "tear/fem/mesh.h"

#include "tear/fem/mesher.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>

namespace tear {

namespace {

Vec3d node(const FemMesh& m, size_t e, int k) {
  return m.nodes[size_t(m.elements[e][size_t(k)])];
}

double sum_squared_edges(const FemMesh& m, size_t e) {
  double s = 0;
  for (int a = 0; a < m.corners(); ++a)
    for (int b = a + 1; b < m.corners(); ++b) s += (node(m, e, a) - node(m, e, b)).squaredNorm();
  return s;
}

// The faces of element e opposite each corner, outward for a positively oriented element
// (3D: the right-hand rule; 2D: the body on the left of a - b).
std::array<std::array<int, 3>, 4> element_faces(const FemMesh& m, size_t e) {
  const std::array<int, 4>& t = m.elements[e];
  if (m.dim == 2) return {{{t[1], t[2], -1}, {t[2], t[0], -1}, {t[0], t[1], -1}, {-1, -1, -1}}};
  return {{{t[1], t[2], t[3]}, {t[0], t[3], t[2]}, {t[0], t[1], t[3]}, {t[0], t[2], t[1]}}};
}

// Its corners in increasing order (the first `dim`: an edge in 2D). Swaps, not std::sort: GCC 12
// warns (-Warray-bounds) about std::sort's unrolled insertion sort on three ints.
std::array<int, 3> sorted_face(std::array<int, 3> f, int dim) {
  if (f[0] > f[1]) std::swap(f[0], f[1]);
  if (dim == 3) {
    if (f[1] > f[2]) std::swap(f[1], f[2]);
    if (f[0] > f[1]) std::swap(f[0], f[1]);
  }
  return f;
}

std::string where(const std::string& name, size_t e) {
  return name + ": element " + std::to_string(e);
}

}  // namespace

double element_volume(const FemMesh& m, size_t e) {
  const Vec3d a = node(m, e, 1) - node(m, e, 0), b = node(m, e, 2) - node(m, e, 0);
  if (m.dim == 2) return 0.5 * (a.x() * b.y() - a.y() * b.x());
  return a.cross(b).dot(node(m, e, 3) - node(m, e, 0)) / 6;
}

double element_quality(const FemMesh& m, size_t e) {
  const double v = element_volume(m, e), l2 = sum_squared_edges(m, e);
  if (!(v > 0) || !(l2 > 0)) return 0;
  return m.dim == 2 ? 4 * std::sqrt(3.0) * v / l2 : 12 * std::pow(3 * v, 2.0 / 3) / l2;
}

MeshFigures mesh_figures(const FemMesh& m) {
  MeshFigures f;
  f.nodes = m.nodes.size();
  f.elements = m.elements.size();
  f.boundary_faces = boundary_faces(m).size();
  f.worst_quality = m.elements.empty() ? 0 : 2;
  f.smallest_height = m.elements.empty() ? 0 : std::numeric_limits<double>::infinity();
  double edges = 0;
  for (size_t e = 0; e < m.elements.size(); ++e) {
    const double v = element_volume(m, e), q = element_quality(m, e);
    f.volume += v;
    if (q < f.worst_quality) f.worst_quality = q, f.worst_element = e;
    // The least altitude: dim V over the largest face (2D: 2 A over the longest edge).
    double largest = 0;
    for (const std::array<int, 3>& face : element_faces(m, e)) {
      if (face[0] < 0) continue;
      const Vec3d a = m.nodes[size_t(face[1])] - m.nodes[size_t(face[0])];
      const double area =
          m.dim == 2 ? a.norm() : 0.5 * a.cross(m.nodes[size_t(face[2])] - m.nodes[size_t(face[0])]).norm();
      largest = std::max(largest, area);
    }
    if (largest > 0) f.smallest_height = std::min(f.smallest_height, m.dim * std::abs(v) / largest);
    edges += std::sqrt(sum_squared_edges(m, e) / (m.dim == 2 ? 3 : 6));
  }
  if (!m.elements.empty()) f.mean_edge = edges / double(m.elements.size());
  return f;
}

void check_fem_mesh(const FemMesh& m, const std::string& name) {
  if (m.elements.empty()) throw std::runtime_error(name + ": the mesh has no elements");
  const int n = int(m.nodes.size());
  for (size_t i = 0; i < m.nodes.size(); ++i)
    if (!m.nodes[i].allFinite())
      throw std::runtime_error(name + ": node " + std::to_string(i) + " is not finite");
  for (size_t e = 0; e < m.elements.size(); ++e) {
    const std::array<int, 4>& t = m.elements[e];
    for (int a = 0; a < m.corners(); ++a) {
      if (t[size_t(a)] < 0 || t[size_t(a)] >= n)
        throw std::runtime_error(where(name, e) + " refers to node " + std::to_string(t[size_t(a)]) +
                                 " of " + std::to_string(n));
      for (int b = 0; b < a; ++b)
        if (t[size_t(a)] == t[size_t(b)])
          throw std::runtime_error(where(name, e) + " uses node " + std::to_string(t[size_t(a)]) +
                                   " twice");
    }
    const double v = element_volume(m, e);
    if (v < 0)
      throw std::runtime_error(where(name, e) + " is inverted (its " +
                               (m.dim == 2 ? "area" : "volume") + " is negative: " +
                               (m.dim == 2 ? "list its corners counter-clockwise"
                                           : "swap two of its corners") + ")");
    if (element_quality(m, e) < 1e-6)
      throw std::runtime_error(where(name, e) + " is degenerate (its corners are " +
                               (m.dim == 2 ? "on a line" : "in a plane") + ")");
  }
  std::map<std::array<int, 3>, int> faces;
  for (size_t e = 0; e < m.elements.size(); ++e)
    for (const std::array<int, 3>& f : element_faces(m, e)) {
      if (f[0] < 0) continue;
      if (++faces[sorted_face(f, m.dim)] > 2)
        throw std::runtime_error(where(name, e) + " is the third element on the " +
                                 (m.dim == 2 ? "edge" : "face") + " of nodes " +
                                 std::to_string(f[0]) + ", " + std::to_string(f[1]) +
                                 (m.dim == 3 ? ", " + std::to_string(f[2]) : "") +
                                 " (the mesh is not a manifold there)");
    }
  // Connected pieces through shared nodes (union-find over nodes).
  std::vector<int> parent(static_cast<size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](int a) {
    while (parent[size_t(a)] != a) a = parent[size_t(a)] = parent[size_t(parent[size_t(a)])];
    return a;
  };
  std::vector<bool> used(size_t(n), false);
  for (const std::array<int, 4>& t : m.elements)
    for (int a = 0; a < m.corners(); ++a) {
      used[size_t(t[size_t(a)])] = true;
      parent[size_t(find(t[size_t(a)]))] = find(t[0]);
    }
  for (int i = 0; i < n; ++i)
    if (!used[size_t(i)])
      throw std::runtime_error(name + ": node " + std::to_string(i) + " belongs to no element");
  const int root = find(m.elements[0][0]);
  for (size_t e = 0; e < m.elements.size(); ++e)
    if (find(m.elements[e][0]) != root)
      throw std::runtime_error(where(name, e) + " is not connected to element 0 (the mesh is in "
                                                "more than one piece: give each piece as an "
                                                "object of its own)");
}

std::vector<std::array<int, 3>> boundary_faces(const FemMesh& m) {
  std::map<std::array<int, 3>, int> count;
  for (size_t e = 0; e < m.elements.size(); ++e)
    for (const std::array<int, 3>& f : element_faces(m, e))
      if (f[0] >= 0) ++count[sorted_face(f, m.dim)];
  std::vector<std::array<int, 3>> out;
  for (size_t e = 0; e < m.elements.size(); ++e)
    for (const std::array<int, 3>& f : element_faces(m, e))
      if (f[0] >= 0 && count[sorted_face(f, m.dim)] == 1) out.push_back(f);
  return out;
}

void orient_elements(FemMesh* m) {
  for (size_t e = 0; e < m->elements.size(); ++e)
    if (element_volume(*m, e) < 0) std::swap(m->elements[e][1], m->elements[e][2]);
}

namespace {

// A closed surface of the shape in its local frame, triangles about `h` across (netgen
// remeshes it at the target size; a finer input keeps curved surfaces close to the shape).
void local_surface(const Shape& s, double h, std::vector<Vec3d>* p,
                   std::vector<std::array<int, 3>>* t) {
  const auto quad = [&](int a, int b, int c, int d) {
    t->push_back({a, b, c});
    t->push_back({a, c, d});
  };
  switch (s.type) {
    case Shape::Type::Box: {
      for (int i = 0; i < 8; ++i)
        p->emplace_back((i & 1) ? s.max.x() : s.min.x(), (i & 2) ? s.max.y() : s.min.y(),
                        (i & 4) ? s.max.z() : s.min.z());
      quad(0, 2, 3, 1), quad(4, 5, 7, 6), quad(0, 1, 5, 4);
      quad(2, 6, 7, 3), quad(0, 4, 6, 2), quad(1, 3, 7, 5);
      return;
    }
    case Shape::Type::Sphere: {
      // An icosahedron, its triangles split in four until their edges are under h / 2.
      const double g = (1 + std::sqrt(5.0)) / 2;
      std::vector<Vec3d> v = {{-1, g, 0}, {1, g, 0},  {-1, -g, 0}, {1, -g, 0},
                              {0, -1, g}, {0, 1, g},  {0, -1, -g}, {0, 1, -g},
                              {g, 0, -1}, {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
      std::vector<std::array<int, 3>> f = {
          {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
          {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
          {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
      for (Vec3d& x : v) x.normalize();
      double edge = (v[0] - v[11]).norm() * s.radius;
      while (edge > 0.5 * h && f.size() < 2000000) {
        std::map<std::pair<int, int>, int> mid;
        const auto middle = [&](int a, int b) {
          const auto key = std::minmax(a, b);
          const auto it = mid.find(key);
          if (it != mid.end()) return it->second;
          v.push_back((v[size_t(a)] + v[size_t(b)]).normalized());
          return mid[key] = int(v.size()) - 1;
        };
        std::vector<std::array<int, 3>> next;
        for (const std::array<int, 3>& tri : f) {
          const int ab = middle(tri[0], tri[1]), bc = middle(tri[1], tri[2]),
                    ca = middle(tri[2], tri[0]);
          next.push_back({tri[0], ab, ca});
          next.push_back({tri[1], bc, ab});
          next.push_back({tri[2], ca, bc});
          next.push_back({ab, bc, ca});
        }
        f.swap(next);
        edge /= 2;
      }
      for (const Vec3d& x : v) p->push_back(s.center + s.radius * x);
      *t = std::move(f);
      return;
    }
    case Shape::Type::Cylinder: {
      const Vec3d axis = s.axis.normalized();
      Vec3d u = axis.unitOrthogonal(), w = axis.cross(u);
      const int nt = std::max(12, int(std::ceil(2 * M_PI * s.radius / (0.5 * h))));
      const int na = std::max(1, int(std::ceil(s.height / (0.5 * h))));
      for (int j = 0; j <= na; ++j)
        for (int i = 0; i < nt; ++i) {
          const double th = 2 * M_PI * i / nt, a = -0.5 * s.height + s.height * j / na;
          p->push_back(s.center + a * axis + s.radius * (std::cos(th) * u + std::sin(th) * w));
        }
      for (int j = 0; j < na; ++j)
        for (int i = 0; i < nt; ++i) {
          const int a = j * nt + i, b = j * nt + (i + 1) % nt;
          quad(a, b, b + nt, a + nt);
        }
      const int bottom = int(p->size()), top = bottom + 1;
      p->push_back(s.center - 0.5 * s.height * axis);
      p->push_back(s.center + 0.5 * s.height * axis);
      for (int i = 0; i < nt; ++i) {
        t->push_back({bottom, (i + 1) % nt, i});
        t->push_back({top, na * nt + i, na * nt + (i + 1) % nt});
      }
      return;
    }
    case Shape::Type::Mesh:
      *p = s.mesh->vertices();
      *t = s.mesh->triangles();
      return;
    default:
      throw std::invalid_argument(
          "an FEM body's shape must be a box, sphere, cylinder or mesh in 3D (a box, sphere or "
          "cylinder in 2D)");
  }
}

// The 2D region's boundary in its local frame, counter-clockwise.
std::vector<BoundarySegment2> local_boundary(const Shape& s) {
  std::vector<BoundarySegment2> out;
  const auto polygon = [&](const std::vector<Eigen::Vector2d>& v) {
    for (size_t i = 0; i < v.size(); ++i) {
      BoundarySegment2 g;
      g.a = v[i];
      g.b = v[(i + 1) % v.size()];
      out.push_back(g);
    }
  };
  switch (s.type) {
    case Shape::Type::Box:
      polygon({{s.min.x(), s.min.y()}, {s.max.x(), s.min.y()}, {s.max.x(), s.max.y()},
               {s.min.x(), s.max.y()}});
      return out;
    case Shape::Type::Sphere: {
      const Eigen::Vector2d c = s.center.head<2>();
      const double r = s.radius;
      const Eigen::Vector2d e[4] = {{r, 0}, {0, r}, {-r, 0}, {0, -r}};
      for (int k = 0; k < 4; ++k) {
        BoundarySegment2 g;
        g.arc = true;
        g.a = c + e[k];
        g.b = c + e[(k + 1) % 4];
        g.c = c + e[k] + e[(k + 1) % 4];
        out.push_back(g);
      }
      return out;
    }
    case Shape::Type::Cylinder: {
      // In 2D the strip |a| <= height / 2, |r| <= radius about the axis.
      const Eigen::Vector2d a = s.axis.head<2>().normalized(), n(-a.y(), a.x());
      const Eigen::Vector2d c = s.center.head<2>();
      const double ha = 0.5 * s.height, r = s.radius;
      polygon({c - ha * a - r * n, c + ha * a - r * n, c + ha * a + r * n, c - ha * a + r * n});
      return out;
    }
    default:
      throw std::invalid_argument(
          "an FEM body's shape must be a box, sphere (a disk) or cylinder (a strip) in 2D");
  }
}

}  // namespace

FemMesh mesh_shape(const Shape& shape, int dim, double h) {
  if (!(h > 0)) throw std::invalid_argument("the mesh size must be positive");
  MeshRequest request;
  request.dim = dim;
  const ShapeTransform& tf = shape.transform;
  request.max_h = h;
  if (dim == 2) {
    // Rotations in 2D are about z, with a uniform scale: circles stay circles.
    const auto world = [&](const Eigen::Vector2d& p) {
      return Eigen::Vector2d(tf.to_world(Vec3d(p.x(), p.y(), 0)).head<2>());
    };
    for (BoundarySegment2 g : local_boundary(shape)) {
      g.a = world(g.a), g.b = world(g.b), g.c = world(g.c);
      request.segments.push_back(g);
    }
  } else {
    std::vector<Vec3d> p;
    local_surface(shape, h / tf.scale, &p, &request.triangles);
    for (const Vec3d& x : p) request.points.push_back(tf.to_world(x));
  }
  MeshResult r = netgen_module().mesh(request);
  if (!r.error.empty()) throw std::runtime_error(r.error);
  FemMesh m;
  m.dim = dim;
  m.nodes = std::move(r.nodes);
  m.elements = std::move(r.elements);
  if (dim == 2)
    for (Vec3d& x : m.nodes) x.z() = 0;
  orient_elements(&m);
  return m;
}

}  // namespace tear
