// math/: signed singular value decomposition (U, V rotations; an inverted F gets a negative
// smallest singular value) and the polar rotation. Used by the SVD-based baseline models.
#pragma once

#include "tear/math/qr.h"
#include "tear/math/types.h"

#include <Eigen/SVD>

#include <cmath>
#include <limits>

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
// for polar_rotation(), and its fallback.
template <int Dim>
inline Mat<Dim> polar_rotation_svd(const Mat<Dim>& F) {
  Mat<Dim> U, V;
  Vec<Dim> sigma;
  signed_svd<Dim>(F, &U, &sigma, &V);
  return U * V.transpose();
}

// The rotation of the polar decomposition F = R S: the rotation closest to F (for an
// inverted F, the rotation of the signed SVD, U V^T above). 2D: closed form. 3D: Higham's
// scaled Newton iteration X <- (g X + X^-T / g) / 2 (Higham 1986), which converges
// quadratically to the orthogonal polar factor; it is used when det F > 0 and converges in a
// few iterations (~10x cheaper than the Jacobi SVD); anything else takes the SVD.
template <int Dim>
inline Mat<Dim> polar_rotation(const Mat<Dim>& F) {
  if constexpr (Dim == 2) {
    const Real c = F(0, 0) + F(1, 1), s = F(1, 0) - F(0, 1);
    const Real n = std::hypot(c, s);
    if (!(n > 0)) return polar_rotation_svd<2>(F);  // F = [a b; b -a]: no unique rotation
    Mat<2> R;
    R << c / n, -s / n, s / n, c / n;
    return R;
  } else {
    constexpr int kMaxIterations = 16;
    // Stop when an update changes X by less than ~1e-6 (double; ~2e-4 in float): quadratic
    // convergence puts the result within ~1e-12 (~float eps) of the limit.
    const Real tol2 = std::sqrt(std::numeric_limits<Real>::epsilon()) * Real(1e-4);
    Mat<3> X = F;
    const Real scale = X.squaredNorm();
    for (int it = 0; it < kMaxIterations; ++it) {
      const Mat<3> cof = cofactor<3>(X);
      const Real det = X.row(0).dot(cof.row(0));
      // X must be safely invertible with det > 0; otherwise (F inverted or nearly
      // singular) the SVD decides.
      if (!(det > Real(1e-9) * scale * std::sqrt(scale))) break;
      const Mat<3> inv_t = cof * (1 / det);  // X^-T
      const Real g = std::sqrt(std::sqrt(inv_t.squaredNorm() / X.squaredNorm()));
      const Mat<3> next = (Real(0.5) * g) * X + (Real(0.5) / g) * inv_t;
      const Real change = (next - X).squaredNorm();
      X = next;
      if (change < tol2) return X;
    }
    return polar_rotation_svd<3>(F);
  }
}

}  // namespace tear
