// math/: QR decomposition by Givens rotations with the sign convention of EQUATIONS.md §2,
// and the cofactor matrix. Header-only: these run once per particle per step.
#pragma once

#include "tear/math/types.h"

#include <cmath>

namespace tear {

namespace qr_detail {

// Rotate rows i and k of R (and columns i and k of Q) so that R(k, col) becomes zero and
// R(i, col) = hypot >= 0. A zero pair is left alone (the rotation is the identity).
template <int Dim>
inline void givens_zero(Mat<Dim>& R, Mat<Dim>& Q, int i, int k, int col) {
  const Real a = R(i, col), b = R(k, col);
  if (b == Real(0)) return;
  const Real h = std::sqrt(a * a + b * b);
  const Real c = a / h, s = b / h;
  for (int j = 0; j < Dim; ++j) {
    const Real ri = R(i, j), rk = R(k, j);
    R(i, j) = c * ri + s * rk;
    R(k, j) = -s * ri + c * rk;
    const Real qi = Q(j, i), qk = Q(j, k);
    Q(j, i) = c * qi + s * qk;
    Q(j, k) = -s * qi + c * qk;
  }
  R(k, col) = 0;
}

}  // namespace qr_detail

// A = Q R with Q a rotation (det +1) and R upper triangular with r11 >= 0 and, in 3D,
// r22 >= 0; det A = prod r_ii, so an inverted A has r_DD < 0 (EQUATIONS.md §2 sign convention).
// Givens rotations never divide by a diagonal entry, so this is defined for every A,
// singular ones included.
template <int Dim>
inline void qr_decompose(const Mat<Dim>& A, Mat<Dim>* Q, Mat<Dim>* R) {
  static_assert(Dim == 2 || Dim == 3, "qr_decompose: 2D or 3D");
  *R = A;
  Q->setIdentity();
  if constexpr (Dim == 2) {
    qr_detail::givens_zero<2>(*R, *Q, 0, 1, 0);
  } else {
    qr_detail::givens_zero<3>(*R, *Q, 1, 2, 0);
    qr_detail::givens_zero<3>(*R, *Q, 0, 1, 0);
    qr_detail::givens_zero<3>(*R, *Q, 1, 2, 1);
  }
  // Givens leaves r11 >= 0 (and r22 >= 0 in 3D) except when the pair it rotated was zero
  // and the entry was already negative; flip pairs of rows/columns so Q stays a rotation.
  auto flip = [&](int a, int b) {
    R->row(a) *= -1;
    R->row(b) *= -1;
    Q->col(a) *= -1;
    Q->col(b) *= -1;
  };
  if constexpr (Dim == 2) {
    if ((*R)(0, 0) < 0) flip(0, 1);
  } else {
    if ((*R)(0, 0) < 0) flip(0, 2);
    if ((*R)(1, 1) < 0) flip(1, 2);
  }
}

// cof(A) = det(A) A^{-T}, written without division (the adjugate transposed).
template <int Dim>
inline Mat<Dim> cofactor(const Mat<Dim>& A) {
  Mat<Dim> C;
  if constexpr (Dim == 2) {
    C << A(1, 1), -A(1, 0), -A(0, 1), A(0, 0);
  } else {
    C(0, 0) = A(1, 1) * A(2, 2) - A(1, 2) * A(2, 1);
    C(0, 1) = A(1, 2) * A(2, 0) - A(1, 0) * A(2, 2);
    C(0, 2) = A(1, 0) * A(2, 1) - A(1, 1) * A(2, 0);
    C(1, 0) = A(0, 2) * A(2, 1) - A(0, 1) * A(2, 2);
    C(1, 1) = A(0, 0) * A(2, 2) - A(0, 2) * A(2, 0);
    C(1, 2) = A(0, 1) * A(2, 0) - A(0, 0) * A(2, 1);
    C(2, 0) = A(0, 1) * A(1, 2) - A(0, 2) * A(1, 1);
    C(2, 1) = A(0, 2) * A(1, 0) - A(0, 0) * A(1, 2);
    C(2, 2) = A(0, 0) * A(1, 1) - A(0, 1) * A(1, 0);
  }
  return C;
}

}  // namespace tear
