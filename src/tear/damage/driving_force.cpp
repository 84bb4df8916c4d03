#include "tear/damage/driving_force.h"

#include "tear/math/svd.h"

#include <Eigen/Eigenvalues>

#include <algorithm>

namespace tear {

template <int Dim>
Mat<Dim> tensile_part(const Mat<Dim>& sym) {
  // Shortcut for definite stresses (pure tension or compression): the characteristic
  // polynomial's coefficients (trace, sum of principal 2x2 minors, determinant) all >= 0
  // mean no negative eigenvalue (Descartes' rule; the roots are real); trace and determinant
  // <= 0 with minors >= 0 mean no positive one.
  const Real c2 = sym.trace(), c0 = sym.determinant();
  Real c1 = 0;
  if constexpr (Dim == 2) {
    c1 = c0;
  } else {
    c1 = sym(0, 0) * sym(1, 1) - sym(0, 1) * sym(1, 0) + sym(0, 0) * sym(2, 2) -
         sym(0, 2) * sym(2, 0) + sym(1, 1) * sym(2, 2) - sym(1, 2) * sym(2, 1);
  }
  if (c1 >= 0) {
    if (c2 >= 0 && c0 >= 0) return sym;
    if (c2 <= 0 && (Dim == 2 || c0 <= 0)) return Mat<Dim>::Zero();
  }
  Eigen::SelfAdjointEigenSolver<Mat<Dim>> eig;
  eig.computeDirect(sym);
  const Vec<Dim> positive = eig.eigenvalues().cwiseMax(Real(0));
  return eig.eigenvectors() * positive.asDiagonal() * eig.eigenvectors().transpose();
}

template <int Dim>
Mat<Dim> structural_tensor(const Mat<Dim>& F, const Mat<Dim>& D, const Real alpha[2]) {
  Mat<Dim> A = Mat<Dim>::Identity();
  if (alpha[0] == 0 && alpha[1] == 0) return A;
  const Mat<Dim> R = polar_rotation<Dim>(F);
  for (int k = 0; k < 2; ++k) {
    if (alpha[k] == 0) continue;
    const Vec<Dim> a = R * D.col(k);
    A += alpha[k] * a * a.transpose();
  }
  return A;
}

template <int Dim>
Real driving_phi(const Mat<Dim>& cauchy, const Mat<Dim>& A, Real sigma_c) {
  const Mat<Dim> s = tensile_part<Dim>(cauchy);
  return (A * s).cwiseProduct(s * A).sum() / (sigma_c * sigma_c);
}

template <int Dim>
Real particle_phi(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                  const Real alpha[2], Real sigma_c) {
  const Real J = F.determinant();
  if (J <= 0) return 0;
  const Mat<Dim> cauchy = first_piola<Dim>(m, F, D) * F.transpose() / J;
  return driving_phi<Dim>(cauchy, structural_tensor<Dim>(F, D, alpha), sigma_c);
}

template Mat<2> tensile_part<2>(const Mat<2>&);
template Mat<3> tensile_part<3>(const Mat<3>&);
template Mat<2> structural_tensor<2>(const Mat<2>&, const Mat<2>&, const Real[2]);
template Mat<3> structural_tensor<3>(const Mat<3>&, const Mat<3>&, const Real[2]);
template Real driving_phi<2>(const Mat<2>&, const Mat<2>&, Real);
template Real driving_phi<3>(const Mat<3>&, const Mat<3>&, Real);
template Real particle_phi<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&, const Real[2],
                              Real);
template Real particle_phi<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&, const Real[2],
                              Real);

}  // namespace tear
