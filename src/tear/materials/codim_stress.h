// materials/: what the codimensional models (surface_qr.h, curve_qr.h; Jiang et al. 2017) share:
// an energy of R alone, F = Q R, whose stress in the Q basis G(R) = Q^T P is a function of R
// (supplement §2: Q^T P R^T is symmetric with the upper triangle of (dPsi/dR) R^T), so that
// P = Q G(R) and dP = dQ G(R) + Q dG(R)[dR] with dQ, dR from qr_differential (supplement §1).
// Also the one-sided contact energy f(x) = k/3 (1 - x)^3 (x < 1, else 0) the models share.
#pragma once

#include "tear/math/qr.h"
#include "tear/math/types.h"

namespace tear::codim {

// f(x) = k/3 (1 - x)^3 for x < 1, 0 for x >= 1, with f' and f'': the energy of a normal column
// (or cross-section area) compressed below its rest length, none when stretched (layers that
// separate pull nothing).
struct OneSided {
  Real f, f1, f2;
};
inline OneSided one_sided(Real k, Real x) {
  if (!(x < 1)) return {0, 0, 0};
  const Real c = 1 - x;
  return {k / 3 * c * c * c, -k * c * c, 2 * k * c};
}

// P = Q G(R) for a model whose stress in the Q basis is `g(R)`.
template <int Dim, class G>
inline Mat<Dim> qr_stress(const Mat<Dim>& F, G&& g) {
  Mat<Dim> Q, R;
  qr_decompose<Dim>(F, &Q, &R);
  return Q * g(R);
}

// dP along dF for the same model, `dg(R, dR)` the differential of G.
template <int Dim, class G, class DG>
inline Mat<Dim> qr_stress_differential(const Mat<Dim>& F, const Mat<Dim>& dF, G&& g, DG&& dg) {
  Mat<Dim> Q, R, dQ, dR;
  qr_decompose<Dim>(F, &Q, &R);
  qr_differential<Dim>(Q, R, dF, &dQ, &dR);
  return dQ * g(R) + Q * dg(R, dR);
}

}  // namespace tear::codim
