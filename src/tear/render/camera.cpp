#include "tear/render/camera.h"

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

namespace tear {

using Eigen::Vector3d;

void Camera::basis(Vector3d* right, Vector3d* up_cam, Vector3d* forward) const {
  const Vector3d f = target - position;
  if (!(f.norm() > 0)) throw std::invalid_argument("camera position equals its target");
  *forward = f.normalized();
  const Vector3d r = forward->cross(up);
  if (!(r.norm() > 1e-9 * up.norm()))
    throw std::invalid_argument("camera up direction is parallel to the view direction");
  *right = r.normalized();
  *up_cam = right->cross(*forward);
}

Vector3d Camera::ray(double px, double py) const {
  Vector3d r, u, f;
  basis(&r, &u, &f);
  const double ty = std::tan(0.5 * fov_deg * M_PI / 180);
  const double tx = ty * width / height;
  const double sx = (2 * px / width - 1) * tx;
  const double sy = (1 - 2 * py / height) * ty;
  return (f + sx * r + sy * u).normalized();
}

bool Camera::project(const Vector3d& p, double* px, double* py) const {
  Vector3d r, u, f;
  basis(&r, &u, &f);
  const Vector3d rel = p - position;
  const double depth = rel.dot(f);
  if (!(depth > 0)) return false;
  const double ty = std::tan(0.5 * fov_deg * M_PI / 180);
  const double tx = ty * width / height;
  *px = 0.5 * width * (1 + rel.dot(r) / depth / tx);
  *py = 0.5 * height * (1 - rel.dot(u) / depth / ty);
  return true;
}

}  // namespace tear
