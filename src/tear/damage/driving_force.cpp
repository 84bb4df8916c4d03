#include "tear/damage/driving_force.h"

#include "tear/math/polar.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tear {

// sigma+ (EQUATIONS.md §1) from the eigenvalues alone, through spectral projectors; no
// eigenvectors.
// 2D: eigenvalues m -+ r. When indefinite (l- < 0 < l+), sigma+ = l+ P+ with the projector
// P+ = (sym - l- I) / (l+ - l-).
// 3D: definite stresses return at once. The characteristic polynomial's coefficients (trace,
// sum of principal 2x2 minors, determinant) all >= 0 mean no negative eigenvalue (Descartes'
// rule; the roots are real); trace and determinant <= 0 with minors >= 0 mean no positive one.
// Otherwise l_max > 0 > l_min, and the eigenvalues come from the trigonometric solution of the
// cubic (as Eigen's computeDirect). If l_mid <= 0, sigma+ = l_max P_max; if l_mid >= 0,
// sigma+ = sym - l_min P_min, with P_max = (sym - l_mid I)(sym - l_min I) /
// ((l_max - l_mid)(l_max - l_min)) (P_min alike), written through the sum and product of the
// two other eigenvalues (from the trace and the minors, exact even when those two coincide).
// Both are well conditioned on their side of l_mid = 0: l_max / (l_max - l_mid) <= 1 when
// l_mid <= 0. When l_mid is within its own error of 0 (round-off, or ~sqrt(eps) rho when it
// is clustered with a neighbour), either form is right to that error; take the one whose
// extreme eigenvalue is farther from 0, so that its projector stays well conditioned.
template <int Dim>
Mat<Dim> tensile_part(const Mat<Dim>& sym) {
  if constexpr (Dim == 2) {
    const Real a = sym(0, 0), d = sym(1, 1), b = sym(1, 0);
    const Real m = (a + d) / 2, h = (a - d) / 2;
    const Real r = std::sqrt(h * h + b * b);
    const Real lo = m - r, hi = m + r;
    if (lo >= 0) return sym;
    if (hi <= 0) return Mat<2>::Zero();
    const Real k = hi / (2 * r);  // r > |m| >= 0 here
    Mat<2> T;
    T << k * (a - lo), k * b, k * b, k * (d - lo);
    return T;
  } else {
    const Real s00 = sym(0, 0), s11 = sym(1, 1), s22 = sym(2, 2);
    const Real a = sym(1, 0), b = sym(2, 0), c = sym(2, 1);
    const Real m12 = s11 * s22 - c * c;
    const Real c2 = s00 + s11 + s22;
    const Real c1 = s00 * s11 - a * a + s00 * s22 - b * b + m12;
    const Real c0 = s00 * m12 - a * (a * s22 - b * c) + b * (a * c - b * s11);
    if (c1 >= 0) {
      if (c2 >= 0 && c0 >= 0) return sym;
      if (c2 <= 0 && c0 <= 0) return Mat<3>::Zero();
    }
    // Trigonometric roots: l = m + 2 rho cos(phi + 2 pi k / 3), rho^2 = |dev|^2 / 6.
    const Real m = c2 * Real(1.0 / 3);
    const Real d0 = s00 - m, d1 = s11 - m, d2 = s22 - m;
    const Real rho2 = (d0 * d0 + d1 * d1 + d2 * d2 + 2 * (a * a + b * b + c * c)) * Real(1.0 / 6);
    const Real det = d0 * d1 * d2 + 2 * a * b * c - d0 * c * c - d1 * b * b - d2 * a * a;
    const Real rho = std::sqrt(rho2);  // > 0: indefinite
    const Real phi =
        std::acos(std::clamp(det / (2 * rho2 * rho), Real(-1), Real(1))) * Real(1.0 / 3);
    const Real rc = rho * std::cos(phi), rs = std::sqrt(Real(3)) * rho * std::sin(phi);
    const Real l_max = m + 2 * rc, l_mid = m - rc + rs, l_min = m - rc - rs;
    // Error bound of l_mid: eps rho (1 + rho / gap), the gap to its nearest neighbour floored
    // at sqrt(eps) rho (the accuracy of a double root of the cubic).
    const Real eps = std::numeric_limits<Real>::epsilon();
    const Real gap = std::max(std::min(l_max - l_mid, l_mid - l_min), std::sqrt(eps) * rho);
    const Real tol = 16 * eps * rho * (rho + gap);
    const bool keep_max = l_mid * gap < -tol ? true : (l_mid * gap > tol ? false : l_max >= -l_min);
    const Real l = keep_max ? l_max : l_min;
    const Real sum = c2 - l, prod = c1 - l * sum;  // of the two other eigenvalues
    const Real k = l / (l * (l - sum) + prod);
    // P = N / ((l - l_a)(l - l_b)) with N = sym^2 - sum sym + prod I (symmetric).
    Mat<3> N;
    N(0, 0) = s00 * s00 + a * a + b * b - sum * s00 + prod;
    N(1, 1) = a * a + s11 * s11 + c * c - sum * s11 + prod;
    N(2, 2) = b * b + c * c + s22 * s22 - sum * s22 + prod;
    N(1, 0) = N(0, 1) = s00 * a + a * s11 + b * c - sum * a;
    N(2, 0) = N(0, 2) = s00 * b + a * c + b * s22 - sum * b;
    N(2, 1) = N(1, 2) = a * b + s11 * c + c * s22 - sum * c;
    if (keep_max) return k * N;
    Mat<3> T;
    T << s00, a, b, a, s11, c, b, c, s22;
    return T - k * N;
  }
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
Mat<Dim> crack_surface_tensor(const Mat<Dim>& F, const Mat<Dim>& D, const double beta[2]) {
  Mat<Dim> M = Mat<Dim>::Identity();
  for (int k = 0; k < 2; ++k) {
    if (beta[k] == 0) continue;
    const Vec<Dim> w = F * D.col(k);
    const Real len2 = w.squaredNorm();
    if (len2 > 0) M += (Real(beta[k]) / len2) * w * w.transpose();
  }
  return M;
}

template <int Dim>
Real driving_phi(const Mat<Dim>& cauchy, const Mat<Dim>& A, Real sigma_c) {
  const Mat<Dim> s = tensile_part<Dim>(cauchy);
  return (A * s).cwiseProduct(s * A).sum() / (sigma_c * sigma_c);
}

// driving_phi(cauchy, structural_tensor(F, D, alpha), sigma_c) without forming A: with
// A = I + sum_k alpha_k b_k b_k^T, b_k = R a_k, u_k = s b_k and s = sigma+ symmetric,
// (A s) : (s A) = tr(s A s A)
//               = |s|^2 + 2 sum_k alpha_k |u_k|^2 + sum_kl alpha_k alpha_l (b_k . u_l)^2.
namespace {

// Phi of a particle; with `excess`, max(Phi - 1, 0) instead, returning 0 early (before the
// rotation and the tensile part) when a bound shows Phi <= 1: with A = I + sum_k alpha_k b_k
// b_k^T, tr(s A s A) <= |s A|^2 <= |A|_2^2 |s|^2 and |s| = |sigma+| <= |sigma|, where the
// eigenvalues of A lie within [1 + sum_k min(alpha_k, 0) |a_k|^2, 1 + sum_k max(alpha_k, 0)
// |a_k|^2] (each alpha_k b_k b_k^T is semi-definite with trace alpha_k |a_k|^2; R keeps lengths).
template <int Dim>
Real phi_of_particle(const Mat<Dim>& P, Real J, const Mat<Dim>& F, const Mat<Dim>& D,
                     const Real alpha[2], Real sigma_c, bool excess) {
  if (J <= 0) return 0;
  const Real inv_sc2 = 1 / (sigma_c * sigma_c);
  const bool fibers = alpha[0] != 0 || alpha[1] != 0;
  Mat<Dim> cauchy;  // P F^T / J, symmetric: the lower triangle, mirrored
  const Real inv_J = 1 / J;
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j <= i; ++j) cauchy(i, j) = cauchy(j, i) = inv_J * P.row(i).dot(F.row(j));
  if (excess) {
    Real hi = 1, lo = 1;
    for (int k = 0; k < 2; ++k) {
      const Real t = alpha[k] * D.col(k).squaredNorm();
      (t > 0 ? hi : lo) += t;
    }
    const Real a_max = std::max(hi, -lo);
    if (a_max * a_max * cauchy.squaredNorm() * inv_sc2 <= 1) return 0;
  }
  const Mat<Dim> s = tensile_part<Dim>(cauchy);
  Real phi = s.squaredNorm();
  if (fibers) {
    const Mat<Dim> R = polar_rotation<Dim>(F);
    Vec<Dim> b[2], u[2];
    for (int k = 0; k < 2; ++k) {
      b[k] = R * D.col(k);
      u[k] = s * b[k];
      phi += 2 * alpha[k] * u[k].squaredNorm();
    }
    for (int k = 0; k < 2; ++k)
      for (int l = 0; l < 2; ++l) {
        const Real bu = b[k].dot(u[l]);
        phi += alpha[k] * alpha[l] * bu * bu;
      }
  }
  phi *= inv_sc2;
  return excess ? std::max(phi - 1, Real(0)) : phi;
}

}  // namespace

template <int Dim>
Real particle_phi(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                  const Real alpha[2], Real sigma_c) {
  return phi_of_particle<Dim>(first_piola<Dim>(m, F, D), F.determinant(), F, D, alpha, sigma_c,
                              false);
}

template <int Dim>
Real phi_excess(const Mat<Dim>& P, Real J, const Mat<Dim>& F, const Mat<Dim>& D,
                const Real alpha[2], Real sigma_c) {
  return phi_of_particle<Dim>(P, J, F, D, alpha, sigma_c, true);
}

template <int Dim>
Real crack_onset_stretch(const MaterialParams& m, const Mat<Dim>& D, const Real alpha[2],
                         Real sigma_c, const Vec<Dim>& n, Real max_stretch) {
  const Vec<Dim> u = n.normalized();
  auto phi = [&](Real e) {
    return particle_phi<Dim>(m, Mat<Dim>::Identity() + e * u * u.transpose(), D, alpha, sigma_c);
  };
  // Scan in steps of 1 % strain (Phi need not be monotone far out), then bisect the first
  // bracket to ~1e-12.
  constexpr Real kStep = Real(0.01);
  Real lo = 0;
  for (Real hi = kStep; hi <= max_stretch - 1 + kStep / 2; lo = hi, hi += kStep) {
    if (phi(hi) < 1) continue;
    for (int it = 0; it < 60; ++it) {
      const Real mid = (lo + hi) / 2;
      (phi(mid) < 1 ? lo : hi) = mid;
    }
    return 1 + hi;
  }
  return std::numeric_limits<Real>::infinity();
}

template Mat<2> tensile_part<2>(const Mat<2>&);
template Mat<3> tensile_part<3>(const Mat<3>&);
template Mat<2> structural_tensor<2>(const Mat<2>&, const Mat<2>&, const Real[2]);
template Mat<3> structural_tensor<3>(const Mat<3>&, const Mat<3>&, const Real[2]);
template Mat<2> crack_surface_tensor<2>(const Mat<2>&, const Mat<2>&, const double[2]);
template Mat<3> crack_surface_tensor<3>(const Mat<3>&, const Mat<3>&, const double[2]);
template Real driving_phi<2>(const Mat<2>&, const Mat<2>&, Real);
template Real driving_phi<3>(const Mat<3>&, const Mat<3>&, Real);
template Real particle_phi<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&, const Real[2],
                              Real);
template Real particle_phi<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&, const Real[2],
                              Real);
template Real crack_onset_stretch<2>(const MaterialParams&, const Mat<2>&, const Real[2], Real,
                                     const Vec<2>&, Real);
template Real crack_onset_stretch<3>(const MaterialParams&, const Mat<3>&, const Real[2], Real,
                                     const Vec<3>&, Real);
template Real phi_excess<2>(const Mat<2>&, Real, const Mat<2>&, const Mat<2>&, const Real[2],
                            Real);
template Real phi_excess<3>(const Mat<3>&, Real, const Mat<3>&, const Mat<3>&, const Real[2],
                            Real);

}  // namespace tear
