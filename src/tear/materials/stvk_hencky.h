// materials/: St. Venant-Kirchhoff with Hencky strain on the signed singular values: energy,
// stress P and its differential dP. Isotropic; ignores fibers and damage.
#pragma once

#include "tear/materials/material.h"

namespace tear {

// Psi = mu |log Sigma|^2 + lambda/2 (tr log Sigma)^2, F = U Sigma V^T the signed SVD, log
// floored (safe_log, helpers.h). The stress plasticity's return maps measure (plasticity.h).
struct StvkHencky {
  static constexpr Model kModel = Model::StvkHencky;
  static constexpr const char* kName = "stvk_hencky";
  static constexpr bool kHasFiberStiffness = false;
  static constexpr bool kDegradedByDamage = false;
  static constexpr int kCodimension = 0;
  static constexpr bool kClosedFormKirchhoff = false;

  // mu, lambda are the Lame parameters of (E, nu) as make_material sets them.
  static void map_parameters(MaterialParams*, Real, Real) {}

  template <int Dim>
  static Real energy(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D, Real g);

  // P = U diag(dPsi/dsigma_i) V^T.
  template <int Dim>
  static Mat<Dim> first_piola(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                              Real g);

  // Analytic through the SVD (isotropic_stress_differential, helpers.h).
  template <int Dim>
  static Mat<Dim> stress_differential(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                                      const Mat<Dim>& dF, Real g);
};

}  // namespace tear
