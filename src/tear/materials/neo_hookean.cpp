#include "tear/materials/neo_hookean.h"

#include "tear/materials/helpers.h"
#include "tear/math/qr.h"

namespace tear {

template <int Dim>
Real NeoHookean::energy(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>&, Real) {
  const Real L = safe_log(F.determinant());
  return m.mu / 2 * (F.squaredNorm() - Dim) - m.mu * L + m.lambda / 2 * L * L;
}

template <int Dim>
Mat<Dim> NeoHookean::first_piola(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>&,
                                 Real) {
  const Real J = F.determinant();
  const Real L = safe_log(J);
  return m.mu * F + (m.lambda * L - m.mu) * safe_log_slope(J) * cofactor<Dim>(F);
}

template <int Dim>
Mat<Dim> NeoHookean::kirchhoff_stress(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>&,
                                      Real) {
  const Real J = F.determinant();
  const Real L = safe_log(J);
  Mat<Dim> tau = m.mu * (F * F.transpose());
  tau.diagonal().array() += (m.lambda * L - m.mu) * safe_log_slope(J) * J;
  return tau;
}

template <int Dim>
Mat<Dim> NeoHookean::stress_differential(const MaterialParams& m, const Mat<Dim>& F,
                                         const Mat<Dim>&, const Mat<Dim>& dF, Real) {
  const Real J = F.determinant();
  const Real L = safe_log(J), L1 = safe_log_slope(J), L2 = safe_log_curvature(J);
  const Mat<Dim> cof = cofactor<Dim>(F);
  const Real dJ = cof.cwiseProduct(dF).sum();
  const Real c = (m.lambda * L - m.mu) * L1;
  const Real dc = (m.lambda * L1 * L1 + (m.lambda * L - m.mu) * L2) * dJ;
  return m.mu * dF + dc * cof + c * cofactor_differential<Dim>(F, dF);
}

template Real NeoHookean::energy<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&, Real);
template Real NeoHookean::energy<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&, Real);
template Mat<2> NeoHookean::first_piola<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&,
                                           Real);
template Mat<3> NeoHookean::first_piola<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&,
                                           Real);
template Mat<2> NeoHookean::kirchhoff_stress<2>(const MaterialParams&, const Mat<2>&,
                                                const Mat<2>&, Real);
template Mat<3> NeoHookean::kirchhoff_stress<3>(const MaterialParams&, const Mat<3>&,
                                                const Mat<3>&, Real);
template Mat<2> NeoHookean::stress_differential<2>(const MaterialParams&, const Mat<2>&,
                                                   const Mat<2>&, const Mat<2>&, Real);
template Mat<3> NeoHookean::stress_differential<3>(const MaterialParams&, const Mat<3>&,
                                                   const Mat<3>&, const Mat<3>&, Real);

}  // namespace tear
