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

CameraView Camera::view() const {
  CameraView v;
  basis(&v.right, &v.up, &v.forward);
  v.eye = position;
  v.ty = std::tan(0.5 * fov_deg * M_PI / 180);
  v.tx = v.ty * width / height;
  v.width = width;
  v.height = height;
  return v;
}

bool CameraView::project(const Vector3d& p, double* px, double* py) const {
  const Vector3d rel = p - eye;
  const double depth = rel.dot(forward);
  if (!(depth > 0)) return false;
  *px = 0.5 * width * (1 + rel.dot(right) / depth / tx);
  *py = 0.5 * height * (1 - rel.dot(up) / depth / ty);
  return true;
}

}  // namespace tear
