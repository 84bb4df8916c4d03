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

// Cylinder and tube: in the meridian half-plane (a = along the axis, r = distance from it)
// the solid is the rectangle |a| <= h/2, r in [ri, R]; the distance there is exact in 3D
// (surface of revolution) and in 2D (two mirrored strips).
double tube_sdf(const Vec3d& p, const Shape& s, double inner) {
  Vec3d axis = unit_axis(s);
  Vec3d d = p - flatten(s.center, s.dim);
  double a = d.dot(axis);
  double r = (d - a * axis).norm();
  double half_w = 0.5 * (s.radius - inner), mid = 0.5 * (s.radius + inner);
  double qa = std::abs(a) - 0.5 * s.height;
  // A solid cylinder has no inner surface: its radial term is r - R, not |r - R/2| - R/2.
  double qr = inner > 0 ? std::abs(r - mid) - half_w : r - s.radius;
  double outside = std::hypot(std::max(qa, 0.0), std::max(qr, 0.0));
  return outside + std::min(std::max(qa, qr), 0.0);
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
      *lo = s.center - Vec3d::Constant(s.radius), *hi = s.center + Vec3d::Constant(s.radius);
      break;
    case Shape::Type::Cylinder:
    case Shape::Type::Tube: {
      // Extent of a capped cylinder along coordinate i: |a_i| h/2 + R sqrt(1 - a_i^2).
      Vec3d a = unit_axis(s), e;
      for (int i = 0; i < 3; ++i)
        e[i] = std::abs(a[i]) * 0.5 * s.height +
               s.radius * std::sqrt(std::max(0.0, 1.0 - a[i] * a[i]));
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
