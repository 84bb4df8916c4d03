#include "tear/geometry/shape.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tear {

namespace {

// In 2D every point and vector lives in the z = 0 plane.
Vec3d flatten(const Vec3d& p, int dim) { return dim == 2 ? Vec3d(p.x(), p.y(), 0) : p; }

Vec3d unit_axis(const Shape& s) {
  Vec3d a = flatten(s.axis, s.dim);
  double n = a.norm();
  return n > 0 ? Vec3d(a / n) : Vec3d::UnitX();
}

// Exact signed distance of the axis-aligned box [lo, hi] (2D: the xy rectangle).
double box_sdf(const Vec3d& p, const Vec3d& lo, const Vec3d& hi, int dim) {
  Vec3d q = (p - 0.5 * (lo + hi)).cwiseAbs() - 0.5 * (hi - lo);
  if (dim == 2) q.z() = -std::numeric_limits<double>::infinity();
  double outside = q.cwiseMax(0.0).norm();
  return outside + std::min(q.maxCoeff(), 0.0);
}

// Coordinates of q about the shape's centre and axis: along the axis, and the distance from it.
Eigen::Vector2d meridian(const Shape& s, const Vec3d& q) {
  const Vec3d axis = unit_axis(s), d = q - flatten(s.center, s.dim);
  const double a = d.dot(axis);
  return Eigen::Vector2d(a, (d - a * axis).norm());
}

// Cylinder and tube: in the meridian half-plane (a = along the axis, r = distance from it)
// the solid is the rectangle |a| <= h/2, r in [ri, R]; the distance there is exact in 3D
// (surface of revolution) and in 2D (two mirrored strips).
double tube_sdf(const Vec3d& p, const Shape& s, double inner) {
  const Eigen::Vector2d m = meridian(s, p);
  const double a = m.x(), r = m.y();
  double half_w = 0.5 * (s.radius - inner), mid = 0.5 * (s.radius + inner);
  double qa = std::abs(a) - 0.5 * s.height;
  // A solid cylinder has no inner surface: its radial term is r - R, not |r - R/2| - R/2.
  double qr = inner > 0 ? std::abs(r - mid) - half_w : r - s.radius;
  double outside = std::hypot(std::max(qa, 0.0), std::max(qr, 0.0));
  return outside + std::min(std::max(qa, qr), 0.0);
}

// Exact signed distance in the plane from q to the simple polygon v[0..n) (any orientation):
// the nearest edge's distance, negative inside (crossing number).
double polygon_sdf(const Eigen::Vector2d* v, int n, const Eigen::Vector2d& q) {
  double d2 = std::numeric_limits<double>::infinity();
  bool inside = false;
  for (int i = 0, j = n - 1; i < n; j = i++) {
    const Eigen::Vector2d e = v[i] - v[j], w = q - v[j];
    const double t = std::clamp(w.dot(e) / e.squaredNorm(), 0.0, 1.0);
    d2 = std::min(d2, (w - t * e).squaredNorm());
    if ((v[i].y() > q.y()) != (v[j].y() > q.y()) &&
        q.x() < v[j].x() + (q.y() - v[j].y()) * e.x() / e.y())
      inside = !inside;
  }
  return inside ? -std::sqrt(d2) : std::sqrt(d2);
}

// Cone / frustum / tapered tube: a solid of revolution whose meridian section is the
// quadrilateral between the inner and outer radius lines; its 2D distance there is the exact
// 3D distance (with a solid cone, the section mirrored across the axis, so that the axis is
// inside rather than a boundary). In 2D the same section is the shape.
double cone_sdf(const Shape& s, const Vec3d& q) {
  const double h = 0.5 * s.height;
  const bool hollow = s.inner_radius > 0 || s.inner_radius_top > 0;
  const Eigen::Vector2d quad[4] = {
      {-h, hollow ? s.inner_radius : -s.radius}, {-h, s.radius}, {h, s.radius_top},
      {h, hollow ? s.inner_radius_top : -s.radius_top}};
  return polygon_sdf(quad, 4, meridian(s, q));
}

// Torus: the distance to the circle of radius R about the axis, less the tube's radius.
double torus_sdf(const Shape& s, const Vec3d& q) {
  const Eigen::Vector2d m = meridian(s, q);
  return std::hypot(m.y() - s.radius, m.x()) - s.tube_radius;
}

// Wedge of a ball or spherical shell between two half-planes through the axis (angle <= pi);
// in 2D a sector of a disk or annulus. Inside the azimuth range the nearest boundary point is
// radial (same azimuth) or on a face; outside it, the nearest point is on a face: a half-annulus
// {rho' >= 0, ri <= |(a, rho')| <= R} in the face's half-plane (the shell has no local minimum
// of distance off p's azimuth), in 2D the segment [ri, R] along the face.
double wedge_sdf(const Shape& s, const Vec3d& q) {
  const Vec3d axis = s.dim == 2 ? Vec3d::UnitZ() : unit_axis(s);
  Vec3d dir = flatten(s.direction, s.dim);
  dir = (dir - dir.dot(axis) * axis).normalized();
  const Vec3d side = axis.cross(dir);
  const Vec3d d = q - flatten(s.center, s.dim);
  const double a = d.dot(axis), x = d.dot(dir), y = d.dot(side);
  const double r = d.norm(), half = 0.5 * s.angle;
  const double shell = std::max(r - s.radius, s.inner_radius - r);  // < 0 between the spheres
  // Each face: the unit vector along it (in the plane normal to the axis) and its normal.
  double face_min = std::numeric_limits<double>::infinity(), plane_max = -face_min;
  for (const double sign : {-1.0, 1.0}) {
    const double c = std::cos(half), sn = sign * std::sin(half);
    const double along = x * c + y * sn;          // rho' in the face's half-plane
    const double off = sign * (y * c - x * sn);   // > 0 beyond this face
    plane_max = std::max(plane_max, off);
    // 2D distance to the half-annulus in the face's half-plane, then with the offset.
    double in_plane;
    if (s.dim == 2) {  // the face is the segment [ri, R] along it (a = 0)
      in_plane = std::max({along - s.radius, s.inner_radius - along, 0.0});
    } else if (along >= 0) {
      const double rr = std::hypot(a, along);
      in_plane = std::max({rr - s.radius, s.inner_radius - rr, 0.0});
    } else {
      const double aa = std::abs(a);
      const double gap = aa > s.radius ? aa - s.radius : aa < s.inner_radius ? s.inner_radius - aa : 0;
      in_plane = std::hypot(along, gap);
    }
    face_min = std::min(face_min, std::hypot(in_plane, off));
  }
  if (plane_max > 0) return face_min;  // outside the azimuth range
  // Within it: outside the shell, the radial distance; inside, the nearest boundary piece.
  if (shell > 0) return shell;
  return std::max(shell, plane_max);
}

// Signed distance in the shape's local frame (before transform).
double local_sdf(const Shape& s, const Vec3d& q) {
  switch (s.type) {
    case Shape::Type::Box:
      return box_sdf(q, flatten(s.min, s.dim), flatten(s.max, s.dim), s.dim);
    case Shape::Type::Sphere:
      return (q - flatten(s.center, s.dim)).norm() - s.radius;
    case Shape::Type::Cylinder:
      return tube_sdf(q, s, 0.0);
    case Shape::Type::Tube:
      return tube_sdf(q, s, s.inner_radius);
    case Shape::Type::HalfSpace: {
      Vec3d n = flatten(s.normal, s.dim);
      double len = n.norm();
      return len > 0 ? (q - flatten(s.point, s.dim)).dot(n) / len : 0.0;
    }
    case Shape::Type::Mesh:
      return s.mesh->signed_distance(q);
    case Shape::Type::Cone:
      return cone_sdf(s, q);
    case Shape::Type::Torus:
      return torus_sdf(s, q);
    case Shape::Type::Wedge:
      return wedge_sdf(s, q);
  }
  return 0.0;
}

// Local-frame axis-aligned bounds (finite shapes only).
void local_bounds(const Shape& s, Vec3d* lo, Vec3d* hi) {
  switch (s.type) {
    case Shape::Type::Box:
      *lo = s.min, *hi = s.max;
      break;
    case Shape::Type::Sphere:
    case Shape::Type::Wedge:  // within its ball
      *lo = s.center - Vec3d::Constant(s.radius), *hi = s.center + Vec3d::Constant(s.radius);
      break;
    case Shape::Type::Cylinder:
    case Shape::Type::Tube:
    case Shape::Type::Cone: {
      // Extent of a capped cylinder along coordinate i: |a_i| h/2 + R sqrt(1 - a_i^2) (a cone
      // lies in the cylinder of its larger radius).
      Vec3d a = unit_axis(s), e;
      const double R = s.type == Shape::Type::Cone ? std::max(s.radius, s.radius_top) : s.radius;
      for (int i = 0; i < 3; ++i)
        e[i] = std::abs(a[i]) * 0.5 * s.height + R * std::sqrt(std::max(0.0, 1.0 - a[i] * a[i]));
      *lo = s.center - e, *hi = s.center + e;
      break;
    }
    case Shape::Type::Torus: {
      // Extent along coordinate i: R sqrt(1 - a_i^2) + r.
      Vec3d a = unit_axis(s), e;
      for (int i = 0; i < 3; ++i)
        e[i] = s.radius * std::sqrt(std::max(0.0, 1.0 - a[i] * a[i])) + s.tube_radius;
      *lo = s.center - e, *hi = s.center + e;
      break;
    }
    case Shape::Type::HalfSpace:
      *lo = Vec3d::Constant(-std::numeric_limits<double>::infinity());
      *hi = -*lo;
      break;
    case Shape::Type::Mesh:
      *lo = s.mesh->lo(), *hi = s.mesh->hi();
      break;
  }
}

}  // namespace

double Shape::sdf(const Vec3d& p) const {
  Vec3d q = flatten(transform.to_local(flatten(p, dim)), dim);
  return transform.scale * local_sdf(*this, q);
}

bool Shape::inside(const Vec3d& p) const {
  if (type == Type::Mesh) return mesh->inside(transform.to_local(flatten(p, dim)));
  return sdf(p) <= 0;
}

Vec3d Shape::normal_at(const Vec3d& p) const {
  Vec3d x = flatten(p, dim);
  if (type == Type::HalfSpace) {
    Vec3d n = flatten(transform.rotate * flatten(normal, dim), dim);
    return n.norm() > 0 ? Vec3d(n.normalized()) : Vec3d::UnitY();
  }
  if (type == Type::Mesh)
    return flatten(transform.rotate * mesh->normal(transform.to_local(x)), dim);
  // Central differences; the step is small relative to the shape's size.
  Vec3d lo, hi;
  bounds(&lo, &hi);
  double h = 1e-6 * std::max(1e-3, (hi - lo).maxCoeff());
  Vec3d g = Vec3d::Zero();
  for (int i = 0; i < dim; ++i) {
    Vec3d e = Vec3d::Zero();
    e[i] = h;
    g[i] = (sdf(x + e) - sdf(x - e)) / (2 * h);
  }
  double n = g.norm();
  return n > 0 ? Vec3d(g / n) : Vec3d::UnitY();
}

void Shape::bounds(Vec3d* lo, Vec3d* hi) const {
  Vec3d llo, lhi;
  local_bounds(*this, &llo, &lhi);
  if (type == Type::HalfSpace) {
    *lo = llo, *hi = lhi;
  } else {
    // Transform the 8 corners of the local box; their bounds contain the shape.
    *lo = Vec3d::Constant(std::numeric_limits<double>::infinity());
    *hi = -*lo;
    for (int c = 0; c < 8; ++c) {
      Vec3d corner((c & 1) ? lhi.x() : llo.x(), (c & 2) ? lhi.y() : llo.y(),
                   (c & 4) ? lhi.z() : llo.z());
      Vec3d w = transform.to_world(flatten(corner, dim));
      *lo = lo->cwiseMin(w), *hi = hi->cwiseMax(w);
    }
  }
  if (dim == 2) lo->z() = hi->z() = 0;
}

Vec3d Shape::world_center() const {
  Vec3d c;
  switch (type) {
    case Type::Box: c = 0.5 * (min + max); break;
    case Type::HalfSpace: c = point; break;
    case Type::Mesh: c = 0.5 * (mesh->lo() + mesh->hi()); break;
    default: c = center; break;
  }
  return flatten(transform.to_world(flatten(c, dim)), dim);
}

}  // namespace tear
