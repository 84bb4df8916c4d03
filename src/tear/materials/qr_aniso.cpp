#include "tear/materials/qr_aniso.h"

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

template <int Dim>
Mat<Dim> QrAniso::stress_differential(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                                      const Mat<Dim>& dF, Real g) {
  const auto stress = [&](const Mat<Dim>& G) { return first_piola<Dim>(m, G, D, g); };
  return numeric_stress_differential<Dim>(stress, F, dF);
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
