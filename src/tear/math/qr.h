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
  const Real inv = 1 / std::sqrt(a * a + b * b);
  const Real c = a * inv, s = b * inv;
  for (int j = col; j < Dim; ++j) {  // columns left of `col` are already zero in both rows
    const Real ri = R(i, j), rk = R(k, j);
    R(i, j) = c * ri + s * rk;
    R(k, j) = -s * ri + c * rk;
  }
  for (int j = 0; j < Dim; ++j) {
    const Real qi = Q(j, i), qk = Q(j, k);
    Q(j, i) = c * qi + s * qk;
    Q(j, k) = -s * qi + c * qk;
  }
  R(k, col) = 0;
}

// The three Givens rotations of a 3x3 QR, unrolled on scalars: (rows 1,2 | col 0), then
// (rows 0,1 | col 0), then (rows 1,2 | col 1). Each rotation is the identity when the entry to
// eliminate is already zero.
inline void rotation(Real a, Real b, Real* c, Real* s) {
  if (b == Real(0)) {
    *c = 1, *s = 0;
    return;
  }
  const Real inv = 1 / std::sqrt(a * a + b * b);
  *c = a * inv, *s = b * inv;
}

inline void givens_qr3(const Mat<3>& A, Mat<3>* Q, Mat<3>* R) {
  Real c1, s1, c2, s2, c3, s3;
  // Rows 1, 2 on column 0.
  rotation(A(1, 0), A(2, 0), &c1, &s1);
  const Real b10 = c1 * A(1, 0) + s1 * A(2, 0);
  const Real b11 = c1 * A(1, 1) + s1 * A(2, 1), b21 = -s1 * A(1, 1) + c1 * A(2, 1);
  const Real b12 = c1 * A(1, 2) + s1 * A(2, 2), b22 = -s1 * A(1, 2) + c1 * A(2, 2);
  // Rows 0, 1 on column 0.
  rotation(A(0, 0), b10, &c2, &s2);
  const Real r11 = c2 * A(0, 0) + s2 * b10;
  const Real r12 = c2 * A(0, 1) + s2 * b11, d11 = -s2 * A(0, 1) + c2 * b11;
  const Real r13 = c2 * A(0, 2) + s2 * b12, d12 = -s2 * A(0, 2) + c2 * b12;
  // Rows 1, 2 on column 1.
  rotation(d11, b21, &c3, &s3);
  const Real r22 = c3 * d11 + s3 * b21;
  const Real r23 = c3 * d12 + s3 * b22, r33 = -s3 * d12 + c3 * b22;
  *R << r11, r12, r13, 0, r22, r23, 0, 0, r33;
  // Q = G1^T G2^T G3^T, where Gk rotates the rows it names.
  const Real q00 = c2, q01 = -s2 * c3, q02 = s2 * s3;  // row 0 of G2^T G3^T
  // Rows 1 and 2 of G2^T G3^T, then G1^T mixes them.
  const Real m10 = s2, m11 = c2 * c3, m12 = -c2 * s3;  // row 1 of G2^T G3^T
  const Real m20 = 0, m21 = s3, m22 = c3;              // row 2 of G2^T G3^T
  *Q << q00, q01, q02,                                  //
      c1 * m10 - s1 * m20, c1 * m11 - s1 * m21, c1 * m12 - s1 * m22,  //
      s1 * m10 + c1 * m20, s1 * m11 + c1 * m21, s1 * m12 + c1 * m22;
}

}  // namespace qr_detail

// A = Q R with Q a rotation (det +1) and R upper triangular with r11 >= 0 and, in 3D,
// r22 >= 0; det A = prod r_ii, so an inverted A has r_DD < 0 (EQUATIONS.md §2 sign convention).
// Givens rotations never divide by a diagonal entry, so this is defined for every A,
// singular ones included.
template <int Dim>
inline void qr_decompose(const Mat<Dim>& A, Mat<Dim>* Q, Mat<Dim>* R) {
  static_assert(Dim == 2 || Dim == 3, "qr_decompose: 2D or 3D");
  if constexpr (Dim == 2) {
    *R = A;
    Q->setIdentity();
    qr_detail::givens_zero<2>(*R, *Q, 0, 1, 0);
  } else {
    qr_detail::givens_qr3(A, Q, R);
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

// Differential of the QR decomposition A = Q R (qr_decompose's convention) along dA, as the
// AnisoMPM supplement §3.4 and Jiang et al. 2017 §1 derive it: Q^T dA = W R + dR with
// W = Q^T dQ skew and dR upper triangular, so the strictly lower part of M = Q^T dA fixes W
// (2D: w = m21 / r11; 3D: w3 = m21 / r11, w2 = -m31 / r11, w1 = (m32 + w2 r12) / r22, with
// W = [[0, -w3, w2], [w3, 0, -w1], [-w2, w1, 0]]); then dR = M - W R and dQ = Q W. It divides by
// r11 (and r22 in 3D): the factorization is not differentiable where they vanish.
template <int Dim>
inline void qr_differential(const Mat<Dim>& Q, const Mat<Dim>& R, const Mat<Dim>& dA, Mat<Dim>* dQ,
                            Mat<Dim>* dR) {
  const Mat<Dim> M = Q.transpose() * dA;
  Mat<Dim> W;
  if constexpr (Dim == 2) {
    const Real w = M(1, 0) / R(0, 0);
    W << 0, -w, w, 0;
  } else {
    const Real w3 = M(1, 0) / R(0, 0), w2 = -M(2, 0) / R(0, 0);
    const Real w1 = (M(2, 1) + w2 * R(0, 1)) / R(1, 1);
    W << 0, -w3, w2, w3, 0, -w1, -w2, w1, 0;
  }
  *dR = M - W * R;
  for (int j = 0; j < Dim; ++j)
    for (int i = j + 1; i < Dim; ++i) (*dR)(i, j) = 0;  // zero up to round-off
  *dQ = Q * W;
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
