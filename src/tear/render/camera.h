// render/: a pinhole camera: rays through pixels and the pixel of a world point.
#pragma once

#include <Eigen/Core>

namespace tear {

// A camera's orthonormal frame and image-plane scale, worked out once for all of a picture's
// rays. Pixel (i, j) covers [i, i + 1) x [j, j + 1) of the image, row 0 at the top.
struct CameraView {
  Eigen::Vector3d eye, right, up, forward;  // `up`: the picture's true up
  double tx = 1, ty = 1;  // half width and half height of the image plane at distance 1
  int width = 1, height = 1;

  // Unit direction of the ray through image point (px, py).
  Eigen::Vector3d ray(double px, double py) const {
    return (forward + ((2 * px / width - 1) * tx) * right + ((1 - 2 * py / height) * ty) * up)
        .normalized();
  }
  // Image point of `p`; false when p is not in front of the camera.
  bool project(const Eigen::Vector3d& p, double* px, double* py) const;
};

struct Camera {
  Eigen::Vector3d position = Eigen::Vector3d(0, 0, 1);
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();  // need not be orthogonal to the view
  double fov_deg = 40;                            // vertical field of view
  int width = 960, height = 540;

  // Orthonormal frame: right, true up, and forward (towards the target). Throws
  // std::invalid_argument when position == target or up is parallel to the view.
  void basis(Eigen::Vector3d* right, Eigen::Vector3d* up_cam, Eigen::Vector3d* forward) const;
  // The frame and scale of basis() with the field of view and picture size (same throws).
  CameraView view() const;
  // Image point of `p`; false when p is not in front of the camera.
  bool project(const Eigen::Vector3d& p, double* px, double* py) const {
    return view().project(p, px, py);
  }
};

}  // namespace tear
