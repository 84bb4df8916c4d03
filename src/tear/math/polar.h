// math/: the rotation R of the polar decomposition F = R S, fast (closed form in 2D, a few
// scalar Halley steps in 3D), with polar_rotation_svd() of svd.h as reference and fallback.
#pragma once

#include "tear/math/qr.h"
#include "tear/math/svd.h"
#include "tear/math/types.h"

#include <cmath>
#include <limits>

namespace tear {

// The rotation of the polar decomposition F = R S: the rotation closest to F, which is U V^T
// of signed_svd() for every F (for an inverted F, S has one negative eigenvalue). Pure and
// deterministic; agrees with polar_rotation_svd() to ~1e-13 (tests/math/polar_test.cpp).
//
// 2D: with F = U diag(s1, s2) V^T (U, V rotations by tu, tv; s1 >= |s2|),
// (F00 + F11, F10 - F01) = (s1 + s2)(cos, sin)(tu - tv) and s1 + s2 >= 0, so the angle of
// that vector is the angle of U V^T, inverted F included. It vanishes only for
// F = [a b; b -a], whose rotation is not unique: the SVD decides.
//
// 3D: from the invariants of the singular values s_i, I1 = |F|^2 = sum s_i^2,
// I2 = |cof F|^2 = sum_{i<j} s_i^2 s_j^2 and J = det F = s1 s2 s3, the sum i1 = s1 + s2 + s3
// is the largest root of q(x) = (x^2 - I1)^2 - 8 J x - 4 I2 (square i1^2 = I1 + 2 i2 and
// i2^2 = I2 + 2 i1 J, i2 = sum_{i<j} s_i s_j); its nearest other root is 2 (s2 + s3) below.
// Cayley-Hamilton for S (S^3 = i1 S^2 - i2 S + J I, with F = R S, cof F = J R S^-1) gives
//   R = (i1 cof F + (i1^2 - i2) F - F F^T F) / D,  D = i1 i2 - J = (s1+s2)(s2+s3)(s1+s3),
// no division by J. i1 comes from Halley's iteration on q from the upper bound
// sqrt(3 I1) >= i1, stopped when the predicted error of the new iterate (cubic convergence)
// is below round-off: 2 steps for strains of ~10%, 2-4 up to ~50%. The error of R is
// ~eps (i1^3 / D)^2, so a nearly rank-one F (s2 + s3 < ~1e-2 s1) takes the SVD, as do
// det F <= 0 (inverted or collapsed particles; rare) and a non-finite F.
template <int Dim>
inline Mat<Dim> polar_rotation(const Mat<Dim>& F) {
  if constexpr (Dim == 2) {
    const Real c = F(0, 0) + F(1, 1), s = F(1, 0) - F(0, 1);
    const Real n2 = c * c + s * s;
    if (!(n2 > 0)) return polar_rotation_svd<2>(F);
    const Real inv = 1 / std::sqrt(n2);
    Mat<2> R;
    R << c * inv, -s * inv, s * inv, c * inv;
    return R;
  } else {
    constexpr Real kEps = std::numeric_limits<Real>::epsilon();
    constexpr int kMaxSteps = 10;
    // Smallest D / i1^3 taken: the error ~eps (i1^3 / D)^2 stays ~1e-12 (double), ~1e-5 (float).
    constexpr Real kMinConditioning = sizeof(Real) >= 8 ? Real(1e-2) : Real(1e-1);
    const Mat<3> cof = cofactor<3>(F);
    const Real J = F(0, 0) * cof(0, 0) + F(0, 1) * cof(0, 1) + F(0, 2) * cof(0, 2);
    if (!(J > 0)) return polar_rotation_svd<3>(F);
    const Real I1 = F.squaredNorm(), I2 = cof.squaredNorm();
    Real x = std::sqrt(3 * I1);
    bool converged = false;
    for (int step = 0; step < kMaxSteps && !converged; ++step) {
      const Real x2 = x * x, a = x2 - I1;
      const Real q = a * a - 8 * J * x - 4 * I2;
      const Real q1 = 4 * x * a - 8 * J;  // q'
      const Real q2 = 12 * x2 - 4 * I1;   // q''
      const Real dx = 2 * q * q1 / (2 * q1 * q1 - q * q2);
      x -= dx;
      // Halley's error after the step: ~|A| dx^3 with A = (q''/2q')^2 - q'''/6q', q''' = 24 x.
      converged = std::abs(dx) * dx * dx * (q2 * q2 + 16 * x * q1) <= 4 * kEps * q1 * q1 * x;
    }
    const Real i2 = (x * x - I1) / 2;
    const Real D = x * i2 - J;
    if (!converged || !(D > kMinConditioning * x * x * x)) return polar_rotation_svd<3>(F);
    Real C[3][3];  // F^T F
    for (int i = 0; i < 3; ++i)
      for (int j = i; j < 3; ++j)
        C[i][j] = C[j][i] = F(0, i) * F(0, j) + F(1, i) * F(1, j) + F(2, i) * F(2, j);
    const Real inv = 1 / D, a = x * inv, b = (x * x - i2) * inv;
    Mat<3> R;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const Real fc = F(i, 0) * C[0][j] + F(i, 1) * C[1][j] + F(i, 2) * C[2][j];
        R(i, j) = a * cof(i, j) + b * F(i, j) - inv * fc;
      }
    return R;
  }
}

}  // namespace tear
