// render/: a pinhole camera: rays through pixels and the pixel of a world point.
#pragma once

#include <Eigen/Core>

namespace tear {

struct Camera {
  Eigen::Vector3d position = Eigen::Vector3d(0, 0, 1);
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();  // need not be orthogonal to the view
  double fov_deg = 40;                            // vertical field of view
  int width = 960, height = 540;

  // Orthonormal frame: right, true up, and forward (towards the target). Throws
  // std::invalid_argument when position == target or up is parallel to the view.
  void basis(Eigen::Vector3d* right, Eigen::Vector3d* up_cam, Eigen::Vector3d* forward) const;
  // Unit direction of the ray through image point (px, py): pixel (i, j) covers
  // [i, i + 1) x [j, j + 1), row 0 at the top.
  Eigen::Vector3d ray(double px, double py) const;
  // Image point of `p`; false when p is not in front of the camera.
  bool project(const Eigen::Vector3d& p, double* px, double* py) const;
};

}  // namespace tear
