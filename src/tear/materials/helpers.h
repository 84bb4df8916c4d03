// materials/: scalar and matrix helpers the model files share (the floored log, the differential
// of the cofactor, the differential of an isotropic stress through the SVD). Pure functions; no
// model knowledge.
#pragma once

#include <Eigen/Geometry>  // cross()
#include <algorithm>
#include <cmath>
#include <limits>

#include "tear/math/qr.h"
#include "tear/math/types.h"

namespace tear {

// log(x) for x >= kLogFloor, continued below it by its second-order Taylor polynomial, so
// that log-based models stay finite (and C2) for collapsed and inverted F. Value, slope and
// curvature (the last for stress differentials).
constexpr Real kLogFloor = Real(1e-2);

inline Real safe_log(Real x) {
  if (x >= kLogFloor) return std::log(x);
  const Real t = (x - kLogFloor) / kLogFloor;
  return std::log(kLogFloor) + t - t * t / 2;
}

inline Real safe_log_slope(Real x) {
  if (x >= kLogFloor) return 1 / x;
  const Real t = (x - kLogFloor) / kLogFloor;
  return (1 - t) / kLogFloor;
}

inline Real safe_log_curvature(Real x) {
  if (x >= kLogFloor) return -1 / (x * x);
  return -1 / (kLogFloor * kLogFloor);
}

// d(cof F) along dF. cof is linear in 2D; in 3D its columns are c1 x c2, c2 x c0, c0 x c1
// (c_j the columns of F), so each differential column is the product rule of one cross product.
template <int Dim>
inline Mat<Dim> cofactor_differential(const Mat<Dim>& F, const Mat<Dim>& dF) {
  if constexpr (Dim == 2) {
    return cofactor<2>(dF);
  } else {
    Mat<3> dC;
    for (int j = 0; j < 3; ++j) {
      const int a = (j + 1) % 3, b = (j + 2) % 3;
      dC.col(j) = dF.col(a).cross(F.col(b)) + F.col(a).cross(dF.col(b));
    }
    return dC;
  }
}

// dP = dP/dF : dF for an isotropic energy psi(sigma) of the signed singular values, F = U diag(sigma)
// V^T, from p = dpsi/dsigma and the Hessian H = d2psi/dsigma2 (Irving-Teran-Fedkiw 2004's
// rotated frame): with G = U^T dF V, the rotated differential U^T dP V has
//   diagonal:            sum_j H_ij G_jj,
//   pairs (i, j), i != j: [a b; b a] [G_ij; G_ji],  a = (s1 + s2)/2, b = (s1 - s2)/2,
//   s1 = (p_i - p_j)/(sigma_i - sigma_j),  s2 = (p_i + p_j)/(sigma_i + sigma_j).
// Where sigma_i ~ sigma_j, s1 is its limit H_ii - H_ij; where sigma_i ~ -sigma_j (an inverted F
// with two singular values of equal size) s2's denominator is floored at the same relative size,
// keeping its sign: the differential stays bounded there.
template <int Dim>
inline Mat<Dim> isotropic_stress_differential(const Mat<Dim>& U, const Vec<Dim>& sigma,
                                              const Mat<Dim>& V, const Vec<Dim>& p,
                                              const Mat<Dim>& H, const Mat<Dim>& dF) {
  const Real tol = std::sqrt(std::numeric_limits<Real>::epsilon()) *
                   std::max(Real(1), sigma.cwiseAbs().maxCoeff());
  const Mat<Dim> G = U.transpose() * dF * V;
  Mat<Dim> dPhat;
  dPhat.diagonal() = H * G.diagonal();
  for (int i = 0; i < Dim; ++i)
    for (int j = i + 1; j < Dim; ++j) {
      const Real diff = sigma[i] - sigma[j], sum = sigma[i] + sigma[j];
      const Real s1 = std::abs(diff) > tol ? (p[i] - p[j]) / diff : H(i, i) - H(i, j);
      const Real s2 = (p[i] + p[j]) / (std::abs(sum) > tol ? sum : std::copysign(tol, sum));
      const Real a = (s1 + s2) / 2, b = (s1 - s2) / 2;
      dPhat(i, j) = a * G(i, j) + b * G(j, i);
      dPhat(j, i) = b * G(i, j) + a * G(j, i);
    }
  return U * dPhat * V.transpose();
}

}  // namespace tear
