#include "tear/materials/material.h"

#include "tear/math/polar.h"
#include "tear/math/qr.h"
#include "tear/math/svd.h"

#include <algorithm>
#include <cmath>

namespace tear {

Real lame_mu(Real E, Real nu) { return E / (2 * (1 + nu)); }
Real lame_lambda(Real E, Real nu) { return E * nu / ((1 + nu) * (1 - 2 * nu)); }

MaterialParams make_material(Model model, Real E, Real nu, Real rho, Real fiber_scale1,
                             Real fiber_scale2) {
  MaterialParams m;
  m.model = model;
  m.E = E;
  m.nu = nu;
  m.rho = rho;
  m.mu = lame_mu(E, nu);
  m.lambda = lame_lambda(E, nu);
  if (model == Model::QrAniso) {
    m.lambda += m.mu;  // EQUATIONS.md §2 small-strain note
    m.kx = fiber_scale1 * m.mu;
    m.ky = fiber_scale2 * m.mu;
  }
  return m;
}

Real wave_speed(const MaterialParams& m) {
  const Real modulus = lame_lambda(m.E, m.nu) + 2 * lame_mu(m.E, m.nu) + std::max(m.kx, m.ky);
  return std::sqrt(modulus / m.rho);
}

const char* model_name(Model m) {
  switch (m) {
    case Model::QrAniso: return "qr_aniso";
    case Model::FixedCorotated: return "fixed_corotated";
    case Model::NeoHookean: return "neo_hookean";
    case Model::StvkHencky: return "stvk_hencky";
  }
  return "?";
}

bool parse_model(const std::string& name, Model* out) {
  for (Model m : {Model::QrAniso, Model::FixedCorotated, Model::NeoHookean, Model::StvkHencky}) {
    if (name == model_name(m)) {
      *out = m;
      return true;
    }
  }
  return false;
}

namespace {

// log(x) for x >= kLogFloor, continued below it by its second-order Taylor polynomial, so
// that log-based models stay finite (and C1) for collapsed and inverted F. Value and slope.
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

// --- qr_aniso (paper §5, EQUATIONS.md §2) ---------------------------------------------
// With F D = Q R: Psi = mu/2 (|R|^2 - d) - mu (J - 1) + lambda/2 (J - 1)^2 + fiber terms.
// The isotropic part depends on R only through |R| = |F| and J = prod r_ii, so its stress
// in the fiber frame is Q (mu R + s cof R) with s = -mu + lambda (J - 1): every entry of
// cof R is a product of entries of R, so nothing divides by r_ii (supplement §3.5).
// Fiber terms: r11 = |F a1| and sqrt(r12^2 + r22^2) = |F a2|, so their stress is
// kx (r11 - 1) Q e1 e1^T + ky (1 - 1/|F a2|) Q (r12 e1 + r22 e2) e2^T.

struct QrEnergyParts {
  Real mu, lambda;  // degraded moduli
};

// Degradation: g multiplies Psi_mu always and Psi_lambda only in tension (J >= 1).
inline QrEnergyParts degraded(const MaterialParams& m, Real J, Real g) {
  return {g * m.mu, J >= 1 ? g * m.lambda : m.lambda};
}

template <int Dim>
Real qr_energy(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D, Real g) {
  Mat<Dim> Q, R;
  qr_decompose<Dim>(F * D, &Q, &R);
  const Real J = R.diagonal().prod();
  const QrEnergyParts p = degraded(m, J, g);
  Real psi = p.mu / 2 * (R.squaredNorm() - Dim) - p.mu * (J - 1) +
             p.lambda / 2 * (J - 1) * (J - 1);
  psi += m.kx / 2 * (R(0, 0) - 1) * (R(0, 0) - 1);
  if constexpr (Dim == 3) {
    const Real n2 = std::sqrt(R(0, 1) * R(0, 1) + R(1, 1) * R(1, 1));
    psi += m.ky / 2 * (n2 - 1) * (n2 - 1);
  }
  return psi;
}

template <int Dim>
Mat<Dim> qr_stress(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D, Real g) {
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

// --- fixed_corotated (Stomakhin et al. 2012): mu |F - R|^2 + lambda/2 (J - 1)^2 ----------

template <int Dim>
Real corotated_energy(const MaterialParams& m, const Mat<Dim>& F) {
  const Real J = F.determinant();
  return m.mu * (F - polar_rotation<Dim>(F)).squaredNorm() + m.lambda / 2 * (J - 1) * (J - 1);
}

template <int Dim>
Mat<Dim> corotated_stress(const MaterialParams& m, const Mat<Dim>& F) {
  const Real J = F.determinant();
  return 2 * m.mu * (F - polar_rotation<Dim>(F)) + m.lambda * (J - 1) * cofactor<Dim>(F);
}

// --- neo_hookean: mu/2 (|F|^2 - d) - mu log J + lambda/2 (log J)^2 -----------------------

template <int Dim>
Real neo_energy(const MaterialParams& m, const Mat<Dim>& F) {
  const Real L = safe_log(F.determinant());
  return m.mu / 2 * (F.squaredNorm() - Dim) - m.mu * L + m.lambda / 2 * L * L;
}

template <int Dim>
Mat<Dim> neo_stress(const MaterialParams& m, const Mat<Dim>& F) {
  const Real J = F.determinant();
  const Real L = safe_log(J);
  return m.mu * F + (m.lambda * L - m.mu) * safe_log_slope(J) * cofactor<Dim>(F);
}

// --- stvk_hencky: mu |log Sigma|^2 + lambda/2 (tr log Sigma)^2 ---------------------------

template <int Dim>
Real hencky_energy(const MaterialParams& m, const Mat<Dim>& F) {
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
Mat<Dim> hencky_stress(const MaterialParams& m, const Mat<Dim>& F) {
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

}  // namespace

template <int Dim>
Real energy_density(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D, Real g) {
  switch (m.model) {
    case Model::QrAniso: return qr_energy<Dim>(m, F, D, g);
    case Model::FixedCorotated: return corotated_energy<Dim>(m, F);
    case Model::NeoHookean: return neo_energy<Dim>(m, F);
    case Model::StvkHencky: return hencky_energy<Dim>(m, F);
  }
  return 0;
}

template <int Dim>
Mat<Dim> first_piola(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D, Real g) {
  switch (m.model) {
    case Model::QrAniso: return qr_stress<Dim>(m, F, D, g);
    case Model::FixedCorotated: return corotated_stress<Dim>(m, F);
    case Model::NeoHookean: return neo_stress<Dim>(m, F);
    case Model::StvkHencky: return hencky_stress<Dim>(m, F);
  }
  return Mat<Dim>::Zero();
}

template <int Dim>
Mat<Dim> degrade_qr_stress(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& P, Real g) {
  const Real J = F.determinant();
  const Real d_mu = (g - 1) * m.mu, d_lambda = J >= 1 ? (g - 1) * m.lambda : Real(0);
  const Mat<Dim> cof = cofactor<Dim>(F);
  return P + d_mu * (F - cof) + (d_lambda * (J - 1)) * cof;
}

template Mat<2> degrade_qr_stress<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&, Real);
template Mat<3> degrade_qr_stress<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&, Real);
template Real energy_density<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&, Real);
template Real energy_density<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&, Real);
template Mat<2> first_piola<2>(const MaterialParams&, const Mat<2>&, const Mat<2>&, Real);
template Mat<3> first_piola<3>(const MaterialParams&, const Mat<3>&, const Mat<3>&, Real);

}  // namespace tear
