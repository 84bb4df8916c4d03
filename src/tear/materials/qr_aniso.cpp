#include "tear/materials/qr_aniso.h"

#include <algorithm>
#include <cmath>

#include "tear/materials/helpers.h"
#include "tear/math/qr.h"

namespace tear {

void QrAniso::map_parameters(MaterialParams* m, Real fiber_scale1, Real fiber_scale2) {
  m->lambda += m->mu;  // EQUATIONS.md §2 small-strain note
  m->kx = fiber_scale1 * m->mu;
  m->ky = fiber_scale2 * m->mu;
}

// With F D = Q R: Psi = mu/2 (|R|^2 - d) - mu (J - 1) + lambda/2 (J - 1)^2 + fiber terms.
// The isotropic part depends on R only through |R| = |F| and J = prod r_ii, so its stress
// in the fiber frame is Q (mu R + s cof R) with s = -mu + lambda (J - 1): every entry of
// cof R is a product of entries of R, so nothing divides by r_ii (supplement §3.5).
// Fiber terms: r11 = |F a1| and sqrt(r12^2 + r22^2) = |F a2|, so their stress is
// kx (r11 - 1) Q e1 e1^T + ky (1 - 1/|F a2|) Q (r12 e1 + r22 e2) e2^T.

namespace {

struct QrEnergyParts {
  Real mu, lambda;  // degraded moduli
};

// Degradation: g multiplies Psi_mu always and Psi_lambda only in tension (J >= 1).
inline QrEnergyParts degraded(const MaterialParams& m, Real J, Real g) {
  return {g * m.mu, J >= 1 ? g * m.lambda : m.lambda};
}

}  // namespace

template <int Dim>
Real QrAniso::energy(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D, Real g) {
  Mat<Dim> Q, R;
  qr_decompose<Dim>(F * D, &Q, &R);
  const Real J = R.diagonal().prod();
  const QrEnergyParts p = degraded(m, J, g);
  Real psi = p.mu / 2 * (R.squaredNorm() - Dim) - p.mu * (J - 1) + p.lambda / 2 * (J - 1) * (J - 1);
  psi += m.kx / 2 * (R(0, 0) - 1) * (R(0, 0) - 1);
  if constexpr (Dim == 3) {
    const Real n2 = std::sqrt(R(0, 1) * R(0, 1) + R(1, 1) * R(1, 1));
    psi += m.ky / 2 * (n2 - 1) * (n2 - 1);
  }
  return psi;
}

template <int Dim>
Mat<Dim> QrAniso::first_piola(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                              Real g) {
  const Mat<Dim> FD = F * D;
  Mat<Dim> Q, R;
  qr_decompose<Dim>(FD, &Q, &R);
  const Real J = R.diagonal().prod();
  const QrEnergyParts p = degraded(m, J, g);
  const Real s = -p.mu + p.lambda * (J - 1);
  // Stress of F D in the rotated frame: Q^T P_D.
  Mat<Dim> S = s * cofactor<Dim>(R);
  S(0, 0) += m.kx * (R(0, 0) - 1);
  if constexpr (Dim == 3) {
    const Real n2 = std::sqrt(R(0, 1) * R(0, 1) + R(1, 1) * R(1, 1));
    if (n2 > 0) {
      const Real c = m.ky * (1 - 1 / n2);
      S(0, 1) += c * R(0, 1);
      S(1, 1) += c * R(1, 1);
    }
  }
  return (p.mu * FD + Q * S) * D.transpose();
}

// The energy depends on R only through |R| = |F|, J = prod r_ii = det F, r11 = |F a1| and, in 3D,
// sqrt(r12^2 + r22^2) = |F a2| (column 2 of R is Q^T F a2, whose third entry is 0). So
//   Psi = g mu/2 (|F|^2 - d) - g mu (J - 1) + lambda_g/2 (J - 1)^2 + sum_k k/2 (|F a_k| - 1)^2,
//   P   = g mu (F - cof F) + lambda_g (J - 1) cof F + sum_k k (n_k - 1) q_k a_k^T,
// (n_k = |F a_k|, q_k = F a_k / n_k), the same P as the QR form, and its differential needs no
// dQ, dR (the supplement's §3.3-3.4 route gives the same dP but divides by r11 and r22):
//   dP = g mu (dF - dcof) + lambda_g (dJ cof F + (J - 1) dcof)
//      + sum_k k [(q.df) q + (1 - 1/n) (df - (q.df) q)] a_k^T,   df = dF a_k.
// At J = 1 it takes the tension side, as the stress does. A fiber squashed to nothing has no
// derivative (the energy has a cone point at n = 0): n is floored at kFiberFloor there.
namespace {

constexpr Real kFiberFloor = Real(1e-6);

template <int Dim>
void add_fiber_differential(Real k, const Vec<Dim>& a, const Mat<Dim>& F, const Mat<Dim>& dF,
                            Mat<Dim>* dP) {
  if (k == 0) return;
  const Vec<Dim> f = F * a, df = dF * a;
  const Real n = f.norm();
  const Vec<Dim> q = n > 0 ? Vec<Dim>(f / n) : Vec<Dim>::Zero();
  const Real qdf = q.dot(df);
  const Vec<Dim> along = qdf * q;
  *dP += k * (along + (1 - 1 / std::max(n, kFiberFloor)) * (df - along)) * a.transpose();
}

}  // namespace

template <int Dim>
Mat<Dim> QrAniso::stress_differential(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                                      const Mat<Dim>& dF, Real g) {
  const Real J = F.determinant();
  const QrEnergyParts p = degraded(m, J, g);
  const Mat<Dim> cof = cofactor<Dim>(F), dcof = cofactor_differential<Dim>(F, dF);
  const Real dJ = cof.cwiseProduct(dF).sum();
  Mat<Dim> dP = p.mu * (dF - dcof) + p.lambda * (dJ * cof + (J - 1) * dcof);
  add_fiber_differential<Dim>(m.kx, D.col(0), F, dF, &dP);
  if constexpr (Dim == 3) add_fiber_differential<Dim>(m.ky, D.col(1), F, dF, &dP);
  return dP;
}

template <int Dim>
Mat<Dim> degrade_qr_stress(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& P, Real g) {
  const Real J = F.determinant();
  const Real d_mu = (g - 1) * m.mu, d_lambda = J >= 1 ? (g - 1) * m.lambda : Real(0);
  const Mat<Dim> cof = cofactor<Dim>(F);
  return P + d_mu * (F - cof) + (d_lambda * (J - 1)) * cof;
}

template Real QrAniso::energy<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&, Real);
template Real QrAniso::energy<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&, Real);
template Mat<2> QrAniso::first_piola<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&, Real);
template Mat<3> QrAniso::first_piola<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&, Real);
template Mat<2> QrAniso::stress_differential<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&,
                                                const Mat<2>&, Real);
template Mat<3> QrAniso::stress_differential<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&,
                                                const Mat<3>&, Real);
template Mat<2> degrade_qr_stress<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&, Real);
template Mat<3> degrade_qr_stress<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&, Real);

}  // namespace tear
