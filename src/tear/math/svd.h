// math/: signed singular value decomposition (U, V rotations; an inverted F gets a negative
// smallest singular value) and the polar rotation through it. Used by the SVD-based baseline
// models; the reference (and fallback) of the fast polar_rotation() in polar.h.
#pragma once

#include "tear/math/types.h"

#include <Eigen/SVD>

namespace tear {

// F = U diag(sigma) V^T with det U = det V = +1, |sigma| sorted descending, only the last
// entry possibly negative.
template <int Dim>
inline void signed_svd(const Mat<Dim>& F, Mat<Dim>* U, Vec<Dim>* sigma, Mat<Dim>* V) {
  Eigen::JacobiSVD<Mat<Dim>, Eigen::NoQRPreconditioner> svd(F,
                                                            Eigen::ComputeFullU | Eigen::ComputeFullV);
  *U = svd.matrixU();
  *V = svd.matrixV();
  *sigma = svd.singularValues();
  if (U->determinant() < 0) {
    U->col(Dim - 1) *= -1;
    (*sigma)[Dim - 1] *= -1;
  }
  if (V->determinant() < 0) {
    V->col(Dim - 1) *= -1;
    (*sigma)[Dim - 1] *= -1;
  }
}

// The rotation of the polar decomposition through the signed SVD: U V^T. The reference
// for polar_rotation() (polar.h), and its fallback.
template <int Dim>
inline Mat<Dim> polar_rotation_svd(const Mat<Dim>& F) {
  Mat<Dim> U, V;
  Vec<Dim> sigma;
  signed_svd<Dim>(F, &U, &sigma, &V);
  return U * V.transpose();
}

}  // namespace tear
