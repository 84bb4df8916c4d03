#include "tear/render/collider_layer.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "tear/render/color_map.h"

namespace tear {

using Eigen::Vector3d;
using Eigen::Vector3f;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// sRGB colours: a slate fill, see-through, and a near-black outline; neither is on the colour
// maps' ramps, so a collider never reads as material.
const Rgb kFill(0.30f, 0.34f, 0.40f), kEdge(0.08f, 0.09f, 0.12f);
constexpr float kFillAlpha = 0.35f, kEdgeAlpha = 0.9f;
// Outline width in pixels (in 2D centred on the boundary, in 3D just outside the silhouette),
// and the largest number of sphere-tracing steps per shape.
constexpr double kEdgePixels = 2;
constexpr int kMaxSteps = 192;

// Where the ray eye + t d enters and leaves the box [lo, hi]; false when it misses.
bool clip_to_box(const Vector3d& eye, const Vector3d& d, const Vector3d& lo, const Vector3d& hi,
                 double* t0, double* t1) {
  double a = 0, b = kInf;
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0) {
      if (eye[k] < lo[k] || eye[k] > hi[k]) return false;
      continue;
    }
    double n = (lo[k] - eye[k]) / d[k], f = (hi[k] - eye[k]) / d[k];
    if (n > f) std::swap(n, f);
    a = std::max(a, n), b = std::min(b, f);
  }
  *t0 = a, *t1 = b;
  return a <= b;
}

}  // namespace

double distance_fade(const Vector3d& p, const Vector3d& center, const Vector3d& up, double size) {
  const Vector3d off = p - center;
  const double dist = (off - off.dot(up) * up).norm() / (2.5 * size);
  return std::exp(-dist * dist);
}

ColliderLayer::ColliderLayer(const std::vector<Shape>& shapes, int dim, const CameraView& view,
                             const Vector3d& up, double ground, const Vector3d& key,
                             const Vector3d& center, double size)
    : dim_(dim),
      eye_(view.eye),
      up_(up),
      key_(key),
      center_(center),
      size_(size),
      pixel_(2 * view.ty / view.height),
      fill_(linear_rgb(kFill)),
      edge_(linear_rgb(kEdge)) {
  for (const Shape& s : shapes) {
    Placed p{&s, Vector3d::Constant(-kInf), Vector3d::Constant(kInf)};
    if (s.type == Shape::Type::HalfSpace) {
      const Vector3d n = s.normal_at(s.transform.to_world(s.point));
      const double height = s.transform.to_world(s.point).dot(up);
      if (n.dot(up) > 0.999 && height <= ground + 1e-9 * size) continue;  // the ground
    } else {
      s.bounds(&p.lo, &p.hi);
      // Room for the outline around the shape: a few pixels at its far side.
      const double reach = (0.5 * (p.lo + p.hi) - eye_).norm() + (p.hi - p.lo).norm();
      const Vector3d pad = Vector3d::Constant(1.5 * kEdgePixels * pixel_ * reach);
      p.lo -= pad, p.hi += pad;
      if (dim == 2) p.lo.z() = p.hi.z() = 0;
    }
    shapes_.push_back(p);
  }
}

bool ColliderLayer::find_2d(const Placed& s, const Vector3d& d, double t_behind, Layer* out) const {
  if (!(d.z() * eye_.z() < 0)) return false;  // the ray does not meet the z = 0 plane ahead
  const double t = -eye_.z() / d.z();
  if (!(t < t_behind)) return false;  // under the ground
  const Vector3d p = eye_ + t * d;
  if ((p.head<2>().array() < s.lo.head<2>().array()).any() ||
      (p.head<2>().array() > s.hi.head<2>().array()).any())
    return false;
  // Seen face on, the plane has no horizon to fade into.
  const double sd = s.shape->sdf(p), w = 0.5 * kEdgePixels * pixel_ * t;
  if (std::abs(sd) < w)
    *out = {t, edge_, kEdgeAlpha};
  else if (sd < 0)
    *out = {t, fill_, kFillAlpha};
  else
    return false;
  return true;
}

bool ColliderLayer::find_3d(const Placed& s, const Vector3d& d, double t_behind, Layer* out) const {
  double t0 = 0, t1 = kInf;
  if (!clip_to_box(eye_, d, s.lo, s.hi, &t0, &t1)) return false;
  // An unbounded shape (a half space) is followed as far as the picture reaches.
  t1 = std::min({t1, t_behind, (center_ - eye_).norm() + 10 * size_});
  if (t0 == 0 && s.shape->sdf(eye_) <= 0) return false;  // the eye is inside: not drawn
  double t = t0, closest = kInf, t_closest = 0;
  for (int step = 0; step < kMaxSteps && t <= t1; ++step) {
    const Vector3d p = eye_ + t * d;
    const double sd = s.shape->sdf(p), w = pixel_ * t;
    if (sd < 0.05 * w) {
      Vector3d n = s.shape->normal_at(p);
      if (n.dot(d) > 0) n = -n;
      const double light = 0.45 + 0.8 * std::max(0.0, n.dot(key_)) + 0.15 * n.dot(up_);
      const float fade = float(distance_fade(p, center_, up_, size_));
      *out = {t, fill_ * float(std::max(0.0, light)), kFillAlpha * fade};
      return true;
    }
    if (sd / w < closest) closest = sd / w, t_closest = t;
    t += sd;
  }
  // Missed: a ray that passed within the outline's width of the surface draws the silhouette.
  if (closest < kEdgePixels && t_closest < t_behind) {
    const float fade = float(distance_fade(eye_ + t_closest * d, center_, up_, size_));
    *out = {t_closest, edge_, kEdgeAlpha * fade};
    return true;
  }
  return false;
}

Vector3f ColliderLayer::over(const Vector3d& d, double t_behind, const Vector3f& behind) const {
  thread_local std::vector<Layer> found;  // kept between calls: no allocation per ray
  found.clear();
  for (const Placed& s : shapes_) {
    Layer l;
    if (dim_ == 2 ? find_2d(s, d, t_behind, &l) : find_3d(s, d, t_behind, &l)) found.push_back(l);
  }
  // Farthest first; ties keep the shapes' order (an insertion sort: few layers, no buffer).
  for (size_t i = 1; i < found.size(); ++i)
    for (size_t j = i; j > 0 && found[j - 1].t < found[j].t; --j) std::swap(found[j - 1], found[j]);
  Vector3f c = behind;
  for (const Layer& l : found) c = (1 - l.alpha) * c + l.alpha * l.color;
  return c;
}

}  // namespace tear
