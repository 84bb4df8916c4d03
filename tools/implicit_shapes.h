// tools/: implicit solids for the shipped meshes (make_meshes.cpp): signed distances of a few
// primitives and the smooth blends that join them (Inigo Quilez, "distance functions" and
// "smooth minimum", iquilezles.org). Negative inside, in the mesh's units.
#pragma once

#include "tear/geometry/shape.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <functional>
#include <utility>
#include <vector>

namespace tear::implicit {

using Sdf = std::function<double(const Vec3d&)>;

// Any of tear's analytic shapes (torus, cone, wedge, ...): its exact signed distance.
inline Sdf shape(const Shape& s) {
  return [s](const Vec3d& p) { return s.sdf(p); };
}

inline Sdf sphere(const Vec3d& c, double r) {
  return [=](const Vec3d& p) { return (p - c).norm() - r; };
}

// Semi-axes `radii` along the columns of `frame` (a rotation), centred on c. Not exact away
// from the surface: |p/r| (|p/r| - 1) / |p/r^2|, a close bound near it.
inline Sdf ellipsoid(const Vec3d& c, const Vec3d& radii,
                     const Eigen::Matrix3d& frame = Eigen::Matrix3d::Identity()) {
  return [=](const Vec3d& p) {
    const Vec3d q = frame.transpose() * (p - c);
    const double k0 = q.cwiseQuotient(radii).norm();
    const double k1 = q.cwiseQuotient(radii.cwiseProduct(radii)).norm();
    return k1 > 0 ? k0 * (k0 - 1) / k1 : -radii.minCoeff();
  };
}

// The hull of the spheres (a, ra) and (b, rb): a capsule when ra = rb; exact.
inline Sdf round_cone(const Vec3d& a, const Vec3d& b, double ra, double rb) {
  return [=](const Vec3d& p) {
    const Vec3d ba = b - a, pa = p - a;
    const double l2 = ba.squaredNorm(), rr = ra - rb, a2 = l2 - rr * rr, il2 = 1 / l2;
    const double y = pa.dot(ba), z = y - l2;
    const double x2 = (pa * l2 - ba * y).squaredNorm(), y2 = y * y * l2, z2 = z * z * l2;
    const double k = (rr > 0 ? 1 : rr < 0 ? -1 : 0) * rr * rr * x2;
    if ((z > 0 ? 1 : z < 0 ? -1 : 0) * a2 * z2 > k) return std::sqrt(x2 + z2) * il2 - rb;
    if ((y > 0 ? 1 : y < 0 ? -1 : 0) * a2 * y2 < k) return std::sqrt(x2 + y2) * il2 - ra;
    return (std::sqrt(x2 * a2 * il2) + y * rr) * il2 - ra;
  };
}

// The box |p - c| <= half with its edges and corners rounded by `round`; exact.
inline Sdf rounded_box(const Vec3d& c, const Vec3d& half, double round) {
  return [=](const Vec3d& p) {
    const Vec3d q = (p - c).cwiseAbs() - half + Vec3d::Constant(round);
    return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0) - round;
  };
}

// The implicit solid f < 0 (f smooth, its gradient non-zero on the surface) as a distance
// near the surface: f / |grad f|, the gradient by central differences of step h.
inline Sdf first_order_distance(std::function<double(const Vec3d&)> f, double h) {
  return [=](const Vec3d& p) {
    Vec3d g;
    for (int d = 0; d < 3; ++d) {
      const Vec3d e = h * Vec3d::Unit(d);
      g[d] = (f(p + e) - f(p - e)) / (2 * h);
    }
    return f(p) / std::max(g.norm(), 1e-12);
  };
}

// Smooth minimum: min(a, b) with the crease filled over a width k (quadratic blend).
inline double smooth_min(double a, double b, double k) {
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - h * h * k / 4;
}

// The union of the parts, each joined to those before it with a fillet of width k.
inline Sdf smooth_union(std::vector<Sdf> parts, double k) {
  return [parts = std::move(parts), k](const Vec3d& p) {
    double d = parts[0](p);
    for (size_t i = 1; i < parts.size(); ++i) d = smooth_min(d, parts[i](p), k);
    return d;
  };
}

// a with b cut away, the cut's edge rounded over a width k (k = 0: a sharp cut).
inline Sdf subtract(Sdf a, Sdf b, double k) {
  return
      [=](const Vec3d& p) { return k > 0 ? -smooth_min(-a(p), b(p), k) : std::max(a(p), -b(p)); };
}

// The common part of a and b, its edges rounded over a width k (k = 0: sharp).
inline Sdf intersect(Sdf a, Sdf b, double k) {
  return
      [=](const Vec3d& p) { return k > 0 ? -smooth_min(-a(p), -b(p), k) : std::max(a(p), b(p)); };
}

// Right-handed rotation by `degrees` about `axis`.
inline Eigen::Matrix3d rotation(const Vec3d& axis, double degrees) {
  return Eigen::AngleAxisd(degrees * M_PI / 180, axis.normalized()).toRotationMatrix();
}

}  // namespace tear::implicit
