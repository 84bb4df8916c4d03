// materials/: scalar and matrix helpers the model files share (the floored log, the differential
// of the cofactor, the numerical stress differential). Pure functions; no model knowledge.
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

// Numerical fallback for dP = dP/dF : dF, for models whose analytic differential is not
// written yet (qr_aniso until EQUATIONS.md §2 "Implicit integration needs dP/dF" lands,
// stvk_hencky). Central differences of `stress` (F -> P) along each entry of F with step
// h = eps^(1/3) max(1, max |F_ij|), contracted with dF. Truncation ~h^2 P''' and round-off
// ~eps P / h: ~1e-10 relative for moderate strains (double), less accurate where P varies on
// scales near h (e.g. a log-based model as J -> 0, where the error grows like (h / J)^2).
// Contracting the entrywise Jacobian, rather than differencing along dF, makes the result linear in
// dF and independent of its scale. Costs up to 2 Dim^2 stress evaluations: fine for a fallback, not
// for a hot loop.
template <int Dim, class Stress>
Mat<Dim> numeric_stress_differential(const Stress& stress, const Mat<Dim>& F, const Mat<Dim>& dF) {
  const Real h =
      std::cbrt(std::numeric_limits<Real>::epsilon()) * std::max(Real(1), F.cwiseAbs().maxCoeff());
  Mat<Dim> dP = Mat<Dim>::Zero();
  for (int j = 0; j < Dim; ++j)
    for (int i = 0; i < Dim; ++i) {
      if (dF(i, j) == 0) continue;
      Mat<Dim> Fp = F, Fm = F;
      Fp(i, j) += h;
      Fm(i, j) -= h;
      // Divide by the step actually taken (F_ij +- h is rounded).
      const Mat<Dim> dP_dFij = (stress(Fp) - stress(Fm)) / (Fp(i, j) - Fm(i, j));
      dP += dF(i, j) * dP_dFij;
    }
  return dP;
}

}  // namespace tear
