#include "tear/materials/stvk_hencky.h"

#include "tear/materials/helpers.h"
#include "tear/math/svd.h"

namespace tear {

template <int Dim>
Real StvkHencky::energy(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>&, Real) {
  Mat<Dim> U, V;
  Vec<Dim> sigma;
  signed_svd<Dim>(F, &U, &sigma, &V);
  Real sum = 0, trace = 0;
  for (int i = 0; i < Dim; ++i) {
    const Real l = safe_log(sigma[i]);
    sum += l * l;
    trace += l;
  }
  return m.mu * sum + m.lambda / 2 * trace * trace;
}

template <int Dim>
Mat<Dim> StvkHencky::first_piola(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>&,
                                 Real) {
  Mat<Dim> U, V;
  Vec<Dim> sigma;
  signed_svd<Dim>(F, &U, &sigma, &V);
  Vec<Dim> l;
  for (int i = 0; i < Dim; ++i) l[i] = safe_log(sigma[i]);
  const Real trace = l.sum();
  Vec<Dim> dpsi;
  for (int i = 0; i < Dim; ++i)
    dpsi[i] = (2 * m.mu * l[i] + m.lambda * trace) * safe_log_slope(sigma[i]);
  return U * dpsi.asDiagonal() * V.transpose();
}

// With l_i = log sigma_i (floored) and T = sum l: p_i = (2 mu l_i + lambda T) l'_i and
// H_ii = (2 mu + lambda) l'_i^2 + (2 mu l_i + lambda T) l''_i, H_ij = lambda l'_i l'_j.
template <int Dim>
Mat<Dim> StvkHencky::stress_differential(const MaterialParams& m, const Mat<Dim>& F,
                                         const Mat<Dim>&, const Mat<Dim>& dF, Real) {
  Mat<Dim> U, V;
  Vec<Dim> sigma;
  signed_svd<Dim>(F, &U, &sigma, &V);
  Vec<Dim> l, l1, l2;
  for (int i = 0; i < Dim; ++i) {
    l[i] = safe_log(sigma[i]);
    l1[i] = safe_log_slope(sigma[i]);
    l2[i] = safe_log_curvature(sigma[i]);
  }
  const Real trace = l.sum();
  Vec<Dim> p;
  Mat<Dim> H;
  for (int i = 0; i < Dim; ++i) {
    const Real t = 2 * m.mu * l[i] + m.lambda * trace;
    p[i] = t * l1[i];
    for (int j = 0; j < Dim; ++j) H(i, j) = m.lambda * l1[i] * l1[j];
    H(i, i) += 2 * m.mu * l1[i] * l1[i] + t * l2[i];
  }
  return isotropic_stress_differential<Dim>(U, sigma, V, p, H, dF);
}

template Real StvkHencky::energy<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&, Real);
template Real StvkHencky::energy<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&, Real);
template Mat<2> StvkHencky::first_piola<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&,
                                           Real);
template Mat<3> StvkHencky::first_piola<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&,
                                           Real);
template Mat<2> StvkHencky::stress_differential<2>(const MaterialParams&, const Mat<2>&,
                                                   const Mat<2>&, const Mat<2>&, Real);
template Mat<3> StvkHencky::stress_differential<3>(const MaterialParams&, const Mat<3>&,
                                                   const Mat<3>&, const Mat<3>&, Real);

}  // namespace tear
