#include "tear/materials/fixed_corotated.h"

#include "tear/materials/helpers.h"
#include "tear/math/polar.h"
#include "tear/math/qr.h"

namespace tear {

template <int Dim>
Real FixedCorotated::energy(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>&, Real) {
  const Real J = F.determinant();
  return m.mu * (F - polar_rotation<Dim>(F)).squaredNorm() + m.lambda / 2 * (J - 1) * (J - 1);
}

template <int Dim>
Mat<Dim> FixedCorotated::first_piola(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>&,
                                     Real) {
  const Real J = F.determinant();
  return 2 * m.mu * (F - polar_rotation<Dim>(F)) + m.lambda * (J - 1) * cofactor<Dim>(F);
}

template <int Dim>
Mat<Dim> polar_rotation_differential(const Mat<Dim>& F, const Mat<Dim>& R, const Mat<Dim>& dF) {
  const Mat<Dim> S = R.transpose() * F;
  const Mat<Dim> M = R.transpose() * dF;
  const Mat<Dim> K = M - M.transpose();
  Mat<Dim> W;
  if constexpr (Dim == 2) {
    const Real w = K(1, 0) / S.trace();
    W << 0, -w, w, 0;
  } else {
    const Vec<3> k(K(2, 1), K(0, 2), K(1, 0));
    const Mat<3> Ssym = (S + S.transpose()) / 2;  // S is symmetric up to round-off
    const Mat<3> A = Ssym.trace() * Mat<3>::Identity() - Ssym;
    const Vec<3> w = A.inverse() * k;
    W << 0, -w[2], w[1], w[2], 0, -w[0], -w[1], w[0], 0;
  }
  return R * W;
}

template <int Dim>
Mat<Dim> FixedCorotated::stress_differential(const MaterialParams& m, const Mat<Dim>& F,
                                             const Mat<Dim>&, const Mat<Dim>& dF, Real) {
  const Mat<Dim> R = polar_rotation<Dim>(F);
  const Mat<Dim> dR = polar_rotation_differential<Dim>(F, R, dF);
  const Mat<Dim> cof = cofactor<Dim>(F);
  const Real J = F.determinant();
  const Real dJ = cof.cwiseProduct(dF).sum();
  return 2 * m.mu * (dF - dR) + m.lambda * dJ * cof +
         m.lambda * (J - 1) * cofactor_differential<Dim>(F, dF);
}

template Real FixedCorotated::energy<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&, Real);
template Real FixedCorotated::energy<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&, Real);
template Mat<2> FixedCorotated::first_piola<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&,
                                               Real);
template Mat<3> FixedCorotated::first_piola<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&,
                                               Real);
template Mat<2> FixedCorotated::stress_differential<2>(const MaterialParams&, const Mat<2>&,
                                                       const Mat<2>&, const Mat<2>&, Real);
template Mat<3> FixedCorotated::stress_differential<3>(const MaterialParams&, const Mat<3>&,
                                                       const Mat<3>&, const Mat<3>&, Real);
template Mat<2> polar_rotation_differential<2>(const Mat<2>&, const Mat<2>&, const Mat<2>&);
template Mat<3> polar_rotation_differential<3>(const Mat<3>&, const Mat<3>&, const Mat<3>&);

}  // namespace tear
