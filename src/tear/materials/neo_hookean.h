// materials/: the compressible neo-Hookean model with a floored log (helpers.h): energy, stress
// P and analytic dP. Isotropic; ignores fibers and damage.
#pragma once

#include "tear/materials/material.h"

namespace tear {

// Psi = mu/2 (|F|^2 - d) - mu L + lambda/2 L^2, L = safe_log(J), J = det F: log J floored so
// that collapsed and inverted F stay finite (docs/materials.md "The models").
struct NeoHookean {
  static constexpr Model kModel = Model::NeoHookean;
  static constexpr const char* kName = "neo_hookean";
  static constexpr bool kHasFiberStiffness = false;
  static constexpr bool kDegradedByDamage = false;
  static constexpr int kCodimension = 0;
  static constexpr bool kClosedFormKirchhoff = true;

  // mu, lambda are the Lame parameters of (E, nu) as make_material sets them.
  static void map_parameters(MaterialParams*, Real, Real) {}

  template <int Dim>
  static Real energy(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D, Real g);

  // P = mu F + (lambda L - mu) L'(J) cof F, L' = safe_log_slope.
  template <int Dim>
  static Mat<Dim> first_piola(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                              Real g);

  // tau = P F^T = mu F F^T + (lambda L - mu) L'(J) J I (cof F F^T = J I): no cofactor and no
  // matrix product, only F F^T (what P2G needs when nothing else uses P).
  template <int Dim>
  static Mat<Dim> kirchhoff_stress(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                                   Real g);

  // With c = (lambda L - mu) L' and dJ = cof F : dF:
  // dP = mu dF + (lambda L'^2 + (lambda L - mu) L'') dJ cof F + c d(cof F).
  template <int Dim>
  static Mat<Dim> stress_differential(const MaterialParams& m, const Mat<Dim>& F, const Mat<Dim>& D,
                                      const Mat<Dim>& dF, Real g);
};

}  // namespace tear
